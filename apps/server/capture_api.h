// The capture endpoints (docs/api.md "Capture sessions", the contract with the WebXR page):
// /api/sessions… and /api/capture/…, over the library's CaptureService. Transport-free like
// api.h: requests in, responses out; no httplib here.
#pragma once
#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "api.h"
#include "caliper/capture/measurement_set.h"

namespace caliper::server {

// Sessions created by devices other than the experimenter's desktop (the headset page creates its
// own). Each costs a PBKDF2 verifier (~0.1 s of CPU) and a row kept until deleted, so a device
// (an IPv4 address or an IPv6 /64) may create `per_device` per `device_window`, and all devices
// together `by_devices` per `devices_window`, whatever addresses they use. The desktop is never
// limited: when devices are refused, the experimenter creates the session there and the headset
// joins it with the code. docs/api.md "Pairing".
struct SessionCreationBudget {
  int per_device = 10;
  std::chrono::seconds device_window = std::chrono::minutes(10);
  int by_devices = 100;
  std::chrono::seconds devices_window = std::chrono::hours(1);
};

struct CaptureApiOptions {
  std::string database;       // sessions.db path; empty: the user's default data folder
  std::string profiles_file;  // optional JSON overriding controller profiles
  bool https = false;                      // for the headset address: the scheme
  std::vector<std::string> headset_hosts;  // for the headset address; empty: the Host the client used
  SessionCreationBudget creation;
  // GET /api/sessions/{id}/mirror-body: the bodies for the session's measurement set, once the
  // request may read the session (api.cpp builds them; empty: 404).
  std::function<ApiResponse(const MeasurementSetFile& set, const ApiRequest& request)> mirror_body;
};

// True for the paths CaptureApi serves.
bool is_capture_path(const std::string& path);
// Loads a controller-profiles file as the capture endpoints will, for a start-up check. Throws the
// library's Error: Io when unreadable, Format when not valid profiles JSON.
void check_capture_profiles_file(const std::string& path);

class CaptureApi {
 public:
  // Cheap: the database is opened on the first request (and retried after a failure).
  explicit CaptureApi(CaptureApiOptions options);
  ~CaptureApi();
  CaptureApi(const CaptureApi&) = delete;
  CaptureApi& operator=(const CaptureApi&) = delete;

  // Thread-safe. Never throws: errors come back in the API's JSON error shape.
  ApiResponse handle(const ApiRequest& request) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace caliper::server
