// The desktop tool's JSON API (docs/api.md), independent of the HTTP transport: a request goes
// in as method, path, query and body; a response comes out as status, content type and bytes.
// Kept free of httplib and Eigen so either side can be tested and replaced on its own.
#pragma once
#include <cstddef>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "caliper/errors.h"

namespace caliper::server {

struct ApiRequest {
  std::string method;                         // "GET", "POST", …
  std::string path;                           // decoded, e.g. "/api/avatar"
  std::map<std::string, std::string> query;   // decoded query parameters
  std::string body;
  std::string content_type;                   // as sent, e.g. "application/json"
  std::map<std::string, std::string> headers; // names lower-cased (e.g. "x-caliper-pairing")
  std::string remote_address;                 // the client's IP address, when known
  std::string local_address;                  // the server's address the client connected to, when known
};

struct ApiResponse {
  int status = 200;
  std::string content_type = "application/json";
  std::string body;
  std::string download_name;  // non-empty: sent as an attachment with this file name
};

// A JSON error body: {"error": {"message", "field", "accepted_range": {min, max, unit} | null, "kind"}}.
// The accepted range is filled in from the measurement catalogue when `field` is a measurement.
ApiResponse error_response(int status, const std::string& message, const std::string& field = {},
                           const std::string& kind = "bad_request");

// The response for a library error (caliper::Error), by its origin: the client's input (values,
// an uploaded document) is a 400 naming the field, a valid request the server cannot serve is
// 422; an error in the server's own files (ErrorOrigin::Installation) is a 500 of the given kind
// (e.g. "model_format" / "model_io" or "database_format" / "database_io") whose message names no
// file or path (the details go to standard error, the server's log).
ApiResponse error_response_for_library_error(const Error& error, const std::string& format_kind,
                                             const std::string& io_kind);

struct ApiOptions {
  std::string models_dir;                   // empty: the library's models folder
  std::string default_model = "mannequin";
  // Capture sessions (/api/sessions…, capture_api.h): the SQLite file (empty: the user's
  // default data folder, opened on first use) and an optional controller-profiles JSON.
  std::string sessions_database;
  std::string capture_profiles_file;
  // The capture page's headset address (GET /api/capture/headset): the scheme the server speaks,
  // and the hosts a headset can reach it at (its LAN addresses when it listens on all
  // interfaces); empty hosts: the host the client used.
  bool https = false;
  std::vector<std::string> headset_hosts;
};

// Routes /api/* requests. Thread-safe: one AvatarBuilder per (model, sex) is created on first use
// and kept for the lifetime of the Api (regressors train once).
// Throws Error(InvalidArgument, field "model"), naming the models found, unless `model` is a
// family in the options' models folder: the check every request's model goes through, for
// `caliper serve --model` to refuse a default no request could use.
void require_known_model(const ApiOptions& options, const std::string& model);

class Api {
 public:
  explicit Api(ApiOptions options = {});
  ~Api();
  Api(const Api&) = delete;
  Api& operator=(const Api&) = delete;

  ApiResponse handle(const ApiRequest& request) const;

  // Loads the model for each sex and trains the preset regressors, so the first request from the
  // page is as fast as the rest. Returns the sexes it prepared; errors are reported, not thrown.
  std::vector<std::string> warm_up(const std::string& model, std::string* problems = nullptr) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace caliper::server
