// The linear limit: what a plain least-squares regression straight from a method's
// inputs to a held-out ANSUR column achieves on the same people. It is the yardstick of
// `caliper eval`: an estimator given the same inputs should predict that column about as well,
// or it loses information on its way through the body model.
#pragma once
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "caliper/io/ansur.h"

namespace caliper {

class LinearLimit {
 public:
  // Fits, for each column, column ≈ c + Σ b_i · input_i by least squares (QR) on the training
  // subjects that have it. Inputs are Virtual Caliper inputs by canonical name (stature, weight,
  // span, crotch_height, hip_breadth, arm_length: virtual_caliper_inputs), SI. Throws
  // Error(InvalidArgument) for an unknown input and Error(Format) when fewer than
  // inputs + 2 training subjects have a column.
  LinearLimit(const std::vector<const AnsurSubject*>& training, std::vector<std::string> inputs,
              const std::vector<std::string>& columns);

  // The prediction for a column from input values (canonical name → SI; extra names ignored).
  // Throws Error(InvalidArgument) for a column not fitted or an input missing.
  double predict(const std::string& column, const std::map<std::string, double>& inputs) const;

  const std::vector<std::string>& inputs() const { return inputs_; }
  const Eigen::VectorXd& coefficients(const std::string& column) const;  // [c, b_1, …, b_n]

 private:
  std::vector<std::string> inputs_;
  std::map<std::string, Eigen::VectorXd> coefficients_;
};

}  // namespace caliper
