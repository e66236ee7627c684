// ISAK repetition rule used by the Virtual Caliper protocol (paper §3.1): take two; if they
// differ by less than 1.5 % use their mean, otherwise take a third and use the median of three.
#pragma once
#include <optional>
#include <string>
#include <vector>

namespace caliper {

enum class IsakRule { MeanOfTwo, MedianOfThree, NeedThird };
const char* to_string(IsakRule rule);

struct IsakResult {
  IsakRule rule = IsakRule::NeedThird;
  std::optional<double> value;    // empty when a third repetition is needed
  double relative_difference = 0; // |a − b| / mean(a, b) of the first two
};

constexpr double kIsakTolerance = 0.015;

// Values must be finite and positive; 2 or 3 of them. Throws Error(InvalidArgument) otherwise.
// With three values whose first two already agree, the third is ignored (rule MeanOfTwo).
IsakResult isak_combine(const std::vector<double>& repetitions);

}  // namespace caliper
