// The capture endpoints (apps/server/capture_api.cpp, CaptureApi::handle): sessions, samples,
// undo/redo, entries, pairing, exports, controller profiles. One live session is created first,
// so "{session}"/"{code}" in an input reach it (api_request.h). CaptureApi::handle is documented
// never to throw, so any exception escaping it is a finding.
#include "api_request.h"
#include "capture_api.h"

using namespace caliper;

namespace {

struct Server {
  server::CaptureApi api{server::CaptureApiOptions{(fuzz::scratch_dir() / "capture.db").string(), {}}};
  std::string session, code;
  Server() {
    server::ApiRequest create{"POST", "/api/sessions", {}, "{}", "application/json", {}, "127.0.0.1", "127.0.0.1"};
    const auto created = nlohmann::json::parse(api.handle(create).body);
    session = created["session"]["id"];
    code = created["pairing_code"];
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static Server server;
  const server::ApiRequest request = fuzz::parse_request(fuzz::as_string(data, size), server.session, server.code);
  fuzz::check_response(server.api.handle(request), request);
  return 0;
}
