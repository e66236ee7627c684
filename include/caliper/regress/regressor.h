// The paper's linear regressors from measurements to shape (§3.4.3): bodies at all 2^K corners
// of β ∈ {−2, +2}^K are measured, and β = A·m + c is fitted by least squares, with the cube root
// of the volume standing in for weight (it is linear in β, weight is not).
#pragma once
#include <Eigen/Core>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "caliper/body/body_model.h"

namespace caliper {

// The paper's presets (§3.4.3): R2 = {stature, weight}; R4 = R2 + {span, crotch_height};
// R5 = R4 + {hip_breadth}; R6 = R5 + {arm_length}.
const std::vector<std::string>& preset_names();  // "R2", "R4", "R5", "R6"
std::vector<std::string> preset_inputs(const std::string& preset);  // throws Error for unknown
// The largest preset whose inputs are all among `known` (by canonical name); throws if not even R2.
std::string auto_preset(const std::vector<std::string>& known);

// The measurement matrix over the corners: one row per corner body, one column per measurement
// of the model (weight column holds cbrt(volume)). Computed once per model and shared.
struct CornerDesign {
  Eigen::MatrixXd betas;                 // 2^K × K
  Eigen::MatrixXd features;              // 2^K × M
  std::vector<std::string> feature_names;  // M, measurement names ("weight" = cbrt volume feature)
};
// `corner_shapes` = how many leading shape directions span the corners (≤ 16; default all, ≤ 10).
CornerDesign build_corner_design(const BodyModel& model, const std::vector<std::string>& measurements,
                                 int corner_shapes = 10);

class Regressor {
 public:
  // Fits β = A·f + c on the design for the given inputs (canonical names, subset of the design).
  Regressor(const CornerDesign& design, std::vector<std::string> inputs, std::string name);

  const std::string& name() const { return name_; }
  const std::vector<std::string>& inputs() const { return inputs_; }
  const Eigen::MatrixXd& coefficients() const { return A_; }  // K × inputs
  const Eigen::VectorXd& intercept() const { return c_; }     // K

  // β for input values in SI units (weight in kg; converted to the volume feature with the
  // model's coefficients). Throws Error if an input is missing or not finite.
  Eigen::VectorXd predict(const BodyModel& model, const std::map<std::string, double>& values) const;

 private:
  std::string name_;
  std::vector<std::string> inputs_;
  Eigen::MatrixXd A_;
  Eigen::VectorXd c_;
};

// Plausibility of shape values (paper §5: values turn red when implausible). Bands:
//   |β_k| ≤ 2 plausible, 2 < |β_k| ≤ 3 unusual, |β_k| > 3 implausible (per value);
//   overall: the worst value, raised to "unusual" when ‖β‖² exceeds the χ²_K 99 % quantile and
//   to "implausible" beyond the 99.9 % quantile.
enum class Verdict { Plausible, Unusual, Implausible };
const char* to_string(Verdict verdict);
struct Plausibility {
  std::vector<Verdict> per_value;
  Verdict overall = Verdict::Plausible;
  double mahalanobis_sq = 0;  // ‖β‖²
  std::string explanation;    // plain words: which values and why
};
Plausibility judge_plausibility(const Eigen::VectorXd& beta);

}  // namespace caliper
