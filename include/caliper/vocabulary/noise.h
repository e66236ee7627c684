// How far Virtual Caliper measurements fall from an ISAK-certified measurer's: paper Table 2,
// written once here. The estimator weighs values with it (regress/map_estimator.h: table2_sd) and
// the evaluation simulates noise with it (evaluation/evaluate.h: table2_mae).
#pragma once
#include <map>
#include <string>

namespace caliper {

// Who took the measurements in VR: the person themselves or someone else (paper §5).
enum class MeasuredBy { Self, Other };

// Paper Table 2: mean absolute error (metres) of the five measured inputs — stature, span,
// arm_length, crotch_height, hip_breadth — by who measured. Weight (a bathroom scale) has none.
const std::map<std::string, double>& paper_table2_mae(MeasuredBy who);

// The SD of a zero-mean Gaussian whose mean absolute error is `mae`: its MAE is SD·√(2/π), so
// SD = MAE·√(π/2).
double gaussian_sd_of_mae(double mae);

}  // namespace caliper
