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

// Plausibility of a body in its model's population (paper §5: values turn red when
// implausible). β ~ N(0, I) over the population: ‖β‖² follows χ²_K and max |β_k| the largest of
// K standard normals; the share of the population's people further out than this body, by the
// rarer of the two (doubled, for testing twice), is its tail probability.
//   overall: plausible, unusual when that share is below 1 %, implausible below 0.1 %;
//   per value (the sliders' colours): |β_k| ≤ 2 plausible, 2 < |β_k| ≤ 3 unusual, > 3 implausible.
// The overall verdict accounts for K: with 20 directions one person in 19 has some |β_k| > 3,
// so a single value beyond 3 colours its slider without making the body implausible.
enum class Verdict { Plausible, Unusual, Implausible };
const char* to_string(Verdict verdict);
struct Plausibility {
  std::vector<Verdict> per_value;
  Verdict overall = Verdict::Plausible;
  double mahalanobis_sq = 0;    // ‖β‖²
  double tail_probability = 1;  // share of the population further from its average (see above)
  std::string rarity;           // the same in words ("rarer than 1 in 1,000 people of that population")
  std::string population;       // whom "population" means: the model's `population` metadata
  std::vector<std::string> drivers;  // what makes the body unusual, in plain words (auto / map)
  std::string explanation;      // plain words: which values and why
};
Plausibility judge_plausibility(const Eigen::VectorXd& beta);

// Upper tail P(X > x) of the χ² distribution with k degrees of freedom (exact closed forms for
// integer k).
double chi_square_tail(int k, double x);

}  // namespace caliper
