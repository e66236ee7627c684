// Least-squares yardstick for the held-out columns (method in the header).
#include "caliper/evaluation/linear_limit.h"

#include <Eigen/QR>
#include <algorithm>

#include "caliper/errors.h"

namespace caliper {

namespace {
const std::vector<std::string>& known_inputs() {
  static const std::vector<std::string> names = {"stature", "weight", "span", "crotch_height", "hip_breadth", "arm_length"};
  return names;
}
}  // namespace

LinearLimit::LinearLimit(const std::vector<const AnsurSubject*>& training, std::vector<std::string> inputs,
                         const std::vector<std::string>& columns)
    : inputs_(std::move(inputs)) {
  for (const auto& name : inputs_)
    if (std::find(known_inputs().begin(), known_inputs().end(), name) == known_inputs().end())
      throw Error(ErrorKind::InvalidArgument, "the linear limit takes Virtual Caliper inputs only, not '" + name + "'", name);
  const auto p = static_cast<Eigen::Index>(inputs_.size()) + 1;
  std::vector<std::map<std::string, double>> features;
  features.reserve(training.size());
  for (const AnsurSubject* s : training) features.push_back(virtual_caliper_inputs(*s));
  for (const auto& column : columns) {
    std::vector<size_t> rows;
    for (size_t i = 0; i < training.size(); ++i)
      if (training[i]->values.count(column)) rows.push_back(i);
    if (static_cast<Eigen::Index>(rows.size()) < p + 1)
      throw Error(ErrorKind::Format,
                  "the linear limit of " + column + " needs at least " + std::to_string(p + 1) + " training subjects with it, got " +
                      std::to_string(rows.size()),
                  column);
    Eigen::MatrixXd x(static_cast<Eigen::Index>(rows.size()), p);
    Eigen::VectorXd y(x.rows());
    for (Eigen::Index r = 0; r < x.rows(); ++r) {
      const size_t i = rows[static_cast<size_t>(r)];
      x(r, 0) = 1;
      for (Eigen::Index c = 1; c < p; ++c) x(r, c) = features[i].at(inputs_[static_cast<size_t>(c - 1)]);
      y(r) = training[i]->values.at(column);
    }
    coefficients_[column] = x.colPivHouseholderQr().solve(y);
  }
}

const Eigen::VectorXd& LinearLimit::coefficients(const std::string& column) const {
  auto it = coefficients_.find(column);
  if (it == coefficients_.end()) throw Error(ErrorKind::InvalidArgument, "no linear limit fitted for " + column, column);
  return it->second;
}

double LinearLimit::predict(const std::string& column, const std::map<std::string, double>& inputs) const {
  const Eigen::VectorXd& b = coefficients(column);
  double out = b(0);
  for (size_t i = 0; i < inputs_.size(); ++i) {
    auto it = inputs.find(inputs_[i]);
    if (it == inputs.end()) throw Error(ErrorKind::InvalidArgument, "the linear limit needs " + inputs_[i], inputs_[i]);
    out += b(static_cast<Eigen::Index>(i) + 1) * it->second;
  }
  return out;
}

}  // namespace caliper
