// From measurements to an avatar: the whole pipeline behind `caliper avatar`, the server and the
// evaluation. Regressors are trained lazily per model and kept (thread-safe) for reuse.
#pragma once
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "caliper/body/body_model.h"
#include "caliper/regress/regressor.h"

namespace caliper {

struct AvatarRequest {
  std::map<std::string, double> measurements;  // canonical name → SI value (m, kg), checked
  std::string regressor = "auto";              // R2, R4, R5, R6, auto, or "custom:a,b,c"
};

struct Avatar {
  std::string regressor;                       // the one used, e.g. "R5"
  std::vector<std::string> inputs;             // the measurements it used
  Eigen::VectorXd beta;                        // K
  Vertices rest_vertices;                      // N×3
  Eigen::MatrixX3d joints;                     // J×3
  Plausibility plausibility;
  std::map<std::string, double> requested;     // SI, as given
  std::map<std::string, double> achieved;      // SI, every measurement the model knows
};

class AvatarBuilder {
 public:
  explicit AvatarBuilder(std::shared_ptr<const BodyModel> model);
  const BodyModel& model() const { return *model_; }

  // Throws Error(Unsupported) when the regressor needs a measurement that was not given or the
  // model lacks, Error(InvalidArgument) for an unknown regressor name.
  Avatar build(const AvatarRequest& request) const;

  // Trained regressor by name (trains on first use; the corner design is shared).
  const Regressor& regressor(const std::string& name, const std::vector<std::string>& inputs) const;

 private:
  std::shared_ptr<const BodyModel> model_;
  mutable std::mutex mutex_;
  mutable std::unique_ptr<CornerDesign> design_;
  mutable std::map<std::string, std::unique_ptr<Regressor>> regressors_;
};

// Checks and converts user-edge values (cm, kg; names or aliases) into a request's SI map.
// Throws Error naming the field and accepted range for NaN, negatives and absurd values.
std::map<std::string, double> measurements_from_edge(const std::map<std::string, double>& edge_values);

}  // namespace caliper
