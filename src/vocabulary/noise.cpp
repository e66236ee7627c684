#include "caliper/vocabulary/noise.h"

#include <cmath>

namespace caliper {

const std::map<std::string, double>& paper_table2_mae(MeasuredBy who) {
  static const std::map<std::string, double> self = {
      {"stature", 0.0153}, {"span", 0.0201}, {"arm_length", 0.0129}, {"crotch_height", 0.0206}, {"hip_breadth", 0.0077}};
  static const std::map<std::string, double> other = {
      {"stature", 0.0147}, {"span", 0.0172}, {"arm_length", 0.0076}, {"crotch_height", 0.0246}, {"hip_breadth", 0.0065}};
  return who == MeasuredBy::Self ? self : other;
}

double gaussian_sd_of_mae(double mae) { return mae * std::sqrt(M_PI / 2); }

}  // namespace caliper
