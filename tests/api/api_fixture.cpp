#include "api_fixture.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "fixtures.h"

namespace caliper::test {

namespace fs = std::filesystem;

namespace {

// The unit tests' toy prism body, with hip breadth and arm length added so every preset (R2–R6)
// can be trained on it. Its three shape values act linearly on every coordinate.
BodyModel toy_api_model(Sex sex) {
  BodyModelData d = toy_model().data();
  d.name = std::string("toy-") + to_string(sex);
  d.sex = sex;
  d.measurements.push_back({"hip_breadth", MeasurementKind::Breadth, {"crotch"}, Axis::Y, "ring 2"});
  d.measurements.push_back({"arm_length", MeasurementKind::Length, {"low", "crotch"}, Axis::Y, "ring 1 to ring 2"});
  return BodyModel(std::move(d));
}

struct Folders {
  fs::path base;
  std::string models, web, secret;
  Folders() {
    base = fs::temp_directory_path() / ("caliper-api-test-" + std::to_string(::getpid()));
    fs::create_directories(base / "models");
    fs::create_directories(base / "web" / "sub");
    for (Sex s : {Sex::Female, Sex::Male})
      save_model(toy_api_model(s), (base / "models" / (std::string("toy-") + to_string(s) + ".npz")).string());
    std::ofstream(base / "web" / "index.html") << "<!doctype html><title>toy</title>";
    std::ofstream(base / "web" / "app.js") << "console.log('toy');";
    std::ofstream(base / "web" / "sub" / "file.txt") << "inside";
    std::ofstream(base / "secret.txt") << "TOP-SECRET";
    // A symlink inside the web root pointing out of it must not be followed.
    std::error_code ec;
    fs::create_symlink(base / "secret.txt", base / "web" / "link.txt", ec);
    models = (base / "models").string();
    web = (base / "web").string();
    secret = (base / "secret.txt").string();
  }
  ~Folders() {
    std::error_code ec;
    fs::remove_all(base, ec);
  }
};

const Folders& folders() {
  static Folders f;
  return f;
}

}  // namespace

const std::string& toy_models_dir() { return folders().models; }
const std::string& toy_web_root() { return folders().web; }
const std::string& secret_file_outside_web_root() { return folders().secret; }

}  // namespace caliper::test
