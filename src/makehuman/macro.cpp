// MakeHuman macro sliders → token weights → target weights (assets README, macro.json).
#include "caliper/makehuman/macro.h"

#include <algorithm>
#include <cmath>

#include "caliper/errors.h"

namespace caliper::makehuman {

namespace {

void check_slider(double v, const char* name) {
  if (!std::isfinite(v) || v < 0 || v > 1)
    throw Error(ErrorKind::OutOfRange, std::string("macro slider ") + name + " must be in [0, 1]", name);
}

// min/average/max with breakpoints 0, 0.5, 1 (muscle, weight, cup size, firmness).
void three_way(std::map<std::string, double>& w, double v, const std::string& suffix) {
  w["min" + suffix] = std::max(0.0, 1 - 2 * v);
  w["average" + suffix] = 1 - std::abs(2 * v - 1);
  w["max" + suffix] = std::max(0.0, 2 * v - 1);
}

}  // namespace

std::map<std::string, double> token_weights(const MacroSliders& s) {
  const std::pair<double, const char*> sliders[] = {
      {s.gender, "gender"}, {s.age, "age"}, {s.muscle, "muscle"}, {s.weight, "weight"},
      {s.height, "height"}, {s.proportions, "proportions"}, {s.cupsize, "cupsize"}, {s.firmness, "firmness"},
      {s.african, "african"}, {s.asian, "asian"}, {s.caucasian, "caucasian"}};
  for (const auto& [v, name] : sliders) check_slider(v, name);
  std::map<std::string, double> w;
  w["female"] = 1 - s.gender;
  w["male"] = s.gender;
  // Age breakpoints 0 (baby), 0.1875 (child), 0.5 (young), 1 (old).
  w["baby"] = w["child"] = w["young"] = w["old"] = 0;
  if (s.age < 0.1875) {
    w["child"] = s.age / 0.1875;
    w["baby"] = 1 - w["child"];
  } else if (s.age < 0.5) {
    w["young"] = (s.age - 0.1875) / 0.3125;
    w["child"] = 1 - w["young"];
  } else {
    w["old"] = (s.age - 0.5) / 0.5;
    w["young"] = 1 - w["old"];
  }
  three_way(w, s.muscle, "muscle");
  three_way(w, s.weight, "weight");
  three_way(w, s.cupsize, "cup");
  three_way(w, s.firmness, "firmness");
  w["minheight"] = std::max(0.0, 1 - 2 * s.height);
  w["maxheight"] = std::max(0.0, 2 * s.height - 1);
  w["uncommonproportions"] = std::max(0.0, 1 - 2 * s.proportions);
  w["idealproportions"] = std::max(0.0, 2 * s.proportions - 1);
  const double race = s.african + s.asian + s.caucasian;
  if (!(race > 0)) throw Error(ErrorKind::InvalidArgument, "race weights must not all be zero", "race");
  w["african"] = s.african / race;
  w["asian"] = s.asian / race;
  w["caucasian"] = s.caucasian / race;
  w["universal"] = 1;
  return w;
}

double target_weight(const std::string& name, const std::map<std::string, double>& tokens) {
  double product = 1;
  size_t start = 0;
  while (start <= name.size()) {
    const size_t end = std::min(name.find('-', start), name.size());
    const std::string token = name.substr(start, end - start);
    auto it = tokens.find(token);
    if (it == tokens.end())
      throw Error(ErrorKind::Format, "macro target '" + name + "' has an unknown token '" + token + "'", name);
    product *= it->second;
    start = end + 1;
  }
  return product;
}

double age_slider(double years) {
  if (!std::isfinite(years)) throw Error(ErrorKind::InvalidArgument, "age must be a finite number of years", "age");
  const double a = years < 25 ? (years - 1) / 48.0 : 0.5 + (years - 25) / 130.0;
  return std::clamp(a, 0.0, 1.0);
}

double modifier_weight(const std::string& name, const std::map<std::string, double>& values) {
  auto ends_with = [&](const std::string& suffix) {
    return name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0;
  };
  const bool incr = ends_with("-incr"), decr = ends_with("-decr");
  if (!incr && !decr) return 0;
  auto it = values.find(name.substr(0, name.size() - 5));
  if (it == values.end()) return 0;
  return incr ? std::max(0.0, it->second) : std::max(0.0, -it->second);
}

}  // namespace caliper::makehuman
