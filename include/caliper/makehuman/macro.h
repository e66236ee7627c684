// MakeHuman's macro sliders and how they weight the macro targets (assets README; the
// combinations listed in targets/macrodetails/macro.json). Every slider is a number in [0, 1]
// turned into piecewise-linear token weights; a target's weight is the product of the weights of
// the tokens in its file name, so the body is multilinear in the token weights.
#pragma once
#include <map>
#include <string>
#include <vector>

namespace caliper::makehuman {

struct MacroSliders {
  double gender = 0.5;       // 0 female … 1 male
  double age = 0.5;          // 0 = 1 year, 0.1875 = 10, 0.5 = 25, 1 = 90
  double muscle = 0.5;
  double weight = 0.5;
  double height = 0.5;
  double proportions = 0.5;  // 0 uncommon … 1 ideal
  double cupsize = 0.5;
  double firmness = 0.5;
  double african = 1.0 / 3, asian = 1.0 / 3, caucasian = 1.0 / 3;  // normalised to sum 1
};

// Token → weight for these sliders ("female", "young", "maxweight", "african", …). Throws
// Error(OutOfRange) naming the slider if one is outside [0, 1] or not finite, and
// Error(InvalidArgument) if the race weights are all zero.
std::map<std::string, double> token_weights(const MacroSliders& sliders);

// Weight of a macro target by name: the product of its '-'-separated tokens' weights; the token
// "universal" weighs 1. Throws Error(Format) naming the target for a token that is not a macro token.
double target_weight(const std::string& target_name, const std::map<std::string, double>& tokens);

// Age slider for an age in years (inverse of the README's mapping), clamped to [0, 1].
double age_slider(double years);

// Local measure modifiers: a signed slider v ∈ [−1, 1] weights "<name>-decr" by max(0, −v) and
// "<name>-incr" by max(0, v). Returns the weight of a modifier target given slider values by
// modifier name (e.g. "measure-waist-circ"); 0 for a modifier not in the map.
double modifier_weight(const std::string& target_name, const std::map<std::string, double>& values);

}  // namespace caliper::makehuman
