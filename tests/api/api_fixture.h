// Shared set-up of the API tests: a models folder with a tiny hand-built body ("toy-female",
// "toy-male") and a web root with a few known files. Eigen-free, so the HTTP tests can include
// httplib.h after it.
#pragma once
#include <string>

namespace caliper::test {

// Created once per test binary under the system temp folder; removed at exit.
const std::string& toy_models_dir();
const std::string& toy_web_root();
// A file next to (outside) the web root that must never be served.
const std::string& secret_file_outside_web_root();

}  // namespace caliper::test
