#include "caliper/vocabulary/weight_change.h"

#include <cmath>
#include <sstream>

#include "caliper/errors.h"

namespace caliper {

void check_weight_change(double pct, const std::string& field) {
  std::ostringstream range;
  range << "[" << kMinWeightChangePct << ", " << kMaxWeightChangePct << "] %";
  if (!std::isfinite(pct))
    throw Error(ErrorKind::InvalidArgument, field + " must be a finite number of percent in " + range.str(), field);
  if (pct < kMinWeightChangePct || pct > kMaxWeightChangePct) {
    std::ostringstream msg;
    msg << field << " = " << pct << " % is outside the accepted range " << range.str();
    throw Error(ErrorKind::OutOfRange, msg.str(), field);
  }
}

}  // namespace caliper
