// The capture endpoints (docs/api.md "Capture sessions", the contract with the WebXR page):
// /api/sessions… and /api/capture/…, over the library's CaptureService. Transport-free like
// api.h: requests in, responses out; no httplib here.
#pragma once
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "api.h"

namespace caliper::server {

struct CaptureApiOptions {
  std::string database;       // sessions.db path; empty: the user's default data folder
  std::string profiles_file;  // optional JSON overriding controller profiles
  bool https = false;                      // for the headset address: the scheme
  std::vector<std::string> headset_hosts;  // for the headset address; empty: the Host the client used
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
