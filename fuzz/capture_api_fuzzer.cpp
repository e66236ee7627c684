// The capture endpoints (apps/server/capture_api.cpp, CaptureApi::handle): sessions, samples,
// undo/redo, entries, pairing, exports, controller profiles. One live session is created first,
// so "{session}"/"{code}" in an input reach it (api_request.h). CaptureApi::handle is documented
// never to throw, so any exception escaping it is a finding.
#include "api_request.h"
#include "capture_api.h"

using namespace caliper;

namespace {

struct Server {
  server::CaptureApi api{server::CaptureApiOptions{(fuzz::scratch_dir() / "capture.db").string(), {}, false, {}, {}, {}}};
  fuzz::LiveSession session = fuzz::create_session(api);
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static Server server;
  return fuzz::handle_input(server.api, server.session, data, size);
}
