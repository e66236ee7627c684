// From measurements to an avatar: the whole pipeline behind `caliper avatar`, the server and the
// evaluation. Regressors are trained lazily per model and kept (thread-safe) for reuse.
#pragma once
#include <cstddef>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "caliper/body/body_model.h"
#include "caliper/detail/lru_cache.h"
#include "caliper/protocol/real_to_virtual.h"
#include "caliper/regress/map_estimator.h"
#include "caliper/regress/regressor.h"

namespace caliper {

struct AvatarRequest {
  std::map<std::string, double> measurements;  // canonical name → SI value (m, kg), checked
  // auto (the default) = map: the noise-aware estimator over every given measurement
  // (regress/map_estimator.h); R2, R4, R5, R6: the paper's presets; or "custom:a,b,c".
  std::string regressor = "auto";
  // For auto / map: who measured (exact | self | other) sets each input's noise SD; `noise_sd`
  // overrides it per measurement (canonical name → SD, SI: m or kg). "exact" (the default, for
  // values whose noise nobody stated) reproduces every input like the paper's regressors do.
  std::string noise = "exact";
  std::map<std::string, double> noise_sd;
  // For "map": also compute the posterior SD of every vertex (the measurements' SDs follow
  // measure_avatar / measure_only).
  bool vertex_uncertainty = true;
  // Apply the model's own real → virtual maps (metadata "real_to_virtual", paper §3.3) to the
  // measurements before regressing: they are real measurements of a person, the regressor
  // needs what the avatar's rest pose shows (e.g. arm length taken with the arm hanging).
  bool apply_model_maps = true;
  // Maps to apply instead of the model's own (a user's file from `caliper map fit`); used only
  // when apply_model_maps is true.
  std::optional<RealToVirtual> maps;
  // Measure only these on the avatar (empty: every measurement the model knows). Evaluation
  // uses it to skip the sections it does not compare.
  std::vector<std::string> measure_only;
  // Measure the avatar at all (false: `achieved` stays empty; for callers that only export).
  bool measure_avatar = true;
};

struct Avatar {
  std::string regressor;                       // the one used: "map" (for auto and map), "R5", …
  std::vector<std::string> inputs;             // the measurements it used
  Eigen::VectorXd beta;                        // K
  Vertices rest_vertices;                      // N×3
  Eigen::MatrixX3d joints;                     // J×3
  Plausibility plausibility;
  std::map<std::string, double> requested;     // SI, as given (measured on the person)
  std::map<std::string, double> targets;       // SI, after real → virtual maps (what was regressed on)
  RealToVirtual real_to_virtual;               // the maps applied to `requested` (identity when none were)
  std::map<std::string, double> achieved;      // SI, the rest-pose body's own, every measurement the model knows
  // Only from "map" (empty otherwise): the noise setting used, the posterior SD of β's
  // measurements (SI, keyed like `achieved`), of each vertex (N, metres, √trace of its 3×3
  // covariance), the K×K covariance of β, how each input fitted.
  // Warnings in plain words, from every regressor: map names an inconsistent input first; the
  // others say when a given value was not used or an input was not reached.
  std::string noise;
  std::map<std::string, double> uncertainty;
  Eigen::VectorXd vertex_sd;
  Eigen::MatrixXd beta_covariance;
  std::map<std::string, MapInputFit> input_fits;
  // auto / map: > 1 when the values lay outside the model's population and the avatar is the
  // closest body inside it (their noise SDs widened by this factor; see MapOptions).
  double noise_widened = 1;
  std::vector<std::string> warnings;
};

class AvatarBuilder {
 public:
  explicit AvatarBuilder(std::shared_ptr<const BodyModel> model);
  const BodyModel& model() const { return *model_; }
  const RealToVirtual& model_maps() const { return maps_; }

  // Throws Error(Unsupported) when the regressor needs a measurement that was not given or the
  // model lacks, Error(InvalidArgument) for an unknown regressor name or noise setting.
  Avatar build(const AvatarRequest& request) const;

  // Trained regressor by name (trains on first use; the corner design is shared). The paper's
  // presets (R2…R6) are kept for the builder's lifetime; other input lists ("custom:…") are kept
  // in a least-recently-used cache of kMaxCustomRegressors and retrained when asked again.
  std::shared_ptr<const Regressor> regressor(const std::string& name, const std::vector<std::string>& inputs) const;
  static constexpr std::size_t kMaxCustomRegressors = 32;
  std::size_t custom_regressor_count() const;  // custom regressors held now (≤ kMaxCustomRegressors)

 private:
  std::shared_ptr<const BodyModel> model_;
  RealToVirtual maps_;
  mutable std::mutex mutex_;
  mutable std::unique_ptr<CornerDesign> design_;
  mutable std::map<std::string, std::shared_ptr<const Regressor>> presets_;
  mutable detail::LruCache<std::string, std::shared_ptr<const Regressor>> custom_{kMaxCustomRegressors};
  MapEstimator map_;  // const and thread-safe: no lock needed

  Avatar build_map(const AvatarRequest& request) const;
  void apply_maps(const AvatarRequest& request, Avatar& avatar) const;  // real_to_virtual and targets
  void finish(const AvatarRequest& request, Avatar& avatar) const;  // body, joints, plausibility, measurements
  void warn_about_inputs(Avatar& avatar) const;  // given values unused or not reached (regressor paths)
};

// A measurement of the avatar as a person would take it (SI): its rest-pose value mapped back
// through the real → virtual map that was applied (arm length with the arm hanging, paper §3.3),
// the rest-pose value itself for every measurement without a map. This is what `requested` is
// compared with. `rest_pose_value` is `avatar.achieved.at(name)`.
double as_measured(const Avatar& avatar, const std::string& name, double rest_pose_value);
// The same for a posterior SD (scaled by the map's slope).
double sd_as_measured(const Avatar& avatar, const std::string& name, double rest_pose_sd);
// Whether `name`'s rest-pose value differs from what a person measures (a non-identity map applied).
bool measured_differs_from_rest_pose(const Avatar& avatar, const std::string& name);

// Checks and converts user-edge values (cm, kg; names or aliases) into a request's SI map.
// Throws Error naming the field and accepted range for NaN, negatives and absurd values.
std::map<std::string, double> measurements_from_edge(const std::map<std::string, double>& edge_values);

// An avatar request as a person states it at the user's edge (CLI options, Python keyword
// arguments): values in cm and kg, by canonical name or alias, not yet checked.
struct EdgeAvatarRequest {
  std::map<std::string, double> measurements;  // name or alias → cm or kg, as typed
  std::string estimator = "auto";              // AvatarRequest::regressor
  std::string noise = "exact";                 // exact | self | other (auto / map)
  std::map<std::string, double> noise_sd;      // name or alias → SD in cm or kg, (0, 50]
  std::optional<RealToVirtual> maps;           // a user's maps instead of the model's own
  bool force = false;                          // use values that look like typing mistakes as given
};
// The checked SI request for `edge`, in the order a person should hear about problems: nothing
// given (Error(InvalidArgument), field "measurements"), values that look swapped or in the wrong
// unit (SuspectInputError, unless `force`), then each value and noise SD (finite, in range,
// known name: Error naming the field and the accepted range). Needs no model, so a bad value is
// reported before a model is loaded; then `AvatarBuilder::build(request)` makes the avatar. This
// is the one way from the edge to an avatar for `caliper avatar` and Python's build_avatar, so
// both give the same avatar for the same values.
AvatarRequest avatar_request_from_edge(const EdgeAvatarRequest& edge);

}  // namespace caliper
