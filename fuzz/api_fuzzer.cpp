// The desktop tool's API (apps/server/api.cpp, Api::handle): every /api/* route, including the
// capture routes it forwards, on the API tests' toy body (tests/api/api_fixture.cpp). Input and
// oracle: api_request.h. Api::handle is documented never to throw, so any exception escaping it,
// caliper::Error included, is a finding.
#include "api_fixture.h"
#include "api_request.h"

using namespace caliper;

namespace {

struct Server {
  server::Api api;
  fuzz::LiveSession session;
  static server::ApiOptions options() {
    server::ApiOptions o;
    o.models_dir = test::toy_models_dir();
    o.default_model = "toy";
    o.sessions_database = (fuzz::scratch_dir() / "sessions.db").string();
    return o;
  }
  Server() : api(options()), session(fuzz::create_session(api)) {}
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static Server server;
  return fuzz::handle_input(server.api, server.session, data, size);
}
