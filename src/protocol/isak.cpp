// ISAK repetition rule (paper §3.1).
#include "caliper/protocol/isak.h"

#include <algorithm>
#include <cmath>

#include "caliper/errors.h"

namespace caliper {

const char* to_string(IsakRule rule) {
  switch (rule) {
    case IsakRule::MeanOfTwo: return "mean_of_two";
    case IsakRule::MedianOfThree: return "median_of_three";
    case IsakRule::NeedThird: return "need_third";
  }
  return "need_third";
}

IsakResult isak_combine(const std::vector<double>& r) {
  if (r.size() < 2 || r.size() > 3)
    throw Error(ErrorKind::InvalidArgument, "ISAK needs 2 or 3 repetitions, got " + std::to_string(r.size()), "repetitions");
  for (size_t i = 0; i < r.size(); ++i)
    if (!std::isfinite(r[i]) || r[i] <= 0)
      throw Error(ErrorKind::InvalidArgument, "repetition " + std::to_string(i + 1) + " must be a positive finite number",
                  "repetitions");
  IsakResult out;
  const double mean = (r[0] + r[1]) / 2;
  out.relative_difference = std::abs(r[0] - r[1]) / mean;
  if (out.relative_difference < kIsakTolerance) {
    out.rule = IsakRule::MeanOfTwo;
    out.value = mean;
  } else if (r.size() == 3) {
    std::vector<double> s = r;
    std::sort(s.begin(), s.end());
    out.rule = IsakRule::MedianOfThree;
    out.value = s[1];
  } else {
    out.rule = IsakRule::NeedThird;
  }
  return out;
}

}  // namespace caliper
