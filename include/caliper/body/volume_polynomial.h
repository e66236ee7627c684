// The body's volume as an exact cubic polynomial in β. Every rest vertex is affine in β
// (T(β) = T̄ + S·β) and the enclosed volume is a sum of triple products of each face's three
// corners (signed tetrahedra, paper §3.4.2), so V(β) is a cubic in the K shape values. Worked out
// once per model, it gives the volume and its gradient in β in O(K³) instead of visiting every
// vertex and face: what the MAP estimator's weight needs at each step (docs/performance.md).
#pragma once
#include <Eigen/Core>
#include <vector>

#include "caliper/body/body_model.h"

namespace caliper {

class VolumePolynomial {
 public:
  // O(F·K² + V·K³) for F faces and the V vertices that own them (about half of all): about
  // 70 ms for the built-in body (33k faces, K = 20) on one core (docs/performance.md).
  // Memory O(K³): keep K to a few dozen.
  explicit VolumePolynomial(const BodyModel& model);

  int shape_count() const { return static_cast<int>(linear_.size()); }
  // V(β) in m³, as signed_volume(model.rest_vertices(β), model.faces()) gives it up to rounding;
  // β may be shorter than K (missing values are 0). Sets `gradient` to ∂V/∂β (size K) if given.
  double value(const Eigen::VectorXd& beta, Eigen::RowVectorXd* gradient = nullptr) const;

 private:
  double constant_ = 0;       // V(0)
  Eigen::VectorXd linear_;    // K
  Eigen::MatrixXd quadratic_; // K×K, symmetric
  Eigen::MatrixXd cubic_;     // K²×K, fully symmetric: cubic_(l + K·m, k) = c_klm
};

}  // namespace caliper
