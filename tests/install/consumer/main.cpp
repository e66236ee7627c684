// Builds a 165 cm, 62 kg woman with an installed Caliper and prints the avatar's stature in cm.
#include <iostream>
#include <memory>

#include "caliper/caliper.h"

int main() {
  auto model = std::make_shared<const caliper::BodyModel>(
      caliper::load_model(std::string(MODELS_DIR) + "/mannequin-female.npz", caliper::Sex::Female));
  caliper::AvatarBuilder builder(model);
  caliper::AvatarRequest request;
  request.measurements = caliper::measurements_from_edge({{"stature", 165}, {"weight", 62}});
  const caliper::Avatar avatar = builder.build(request);
  std::cout << avatar.achieved.at("stature") * 100 << "\n";
  return 0;
}
