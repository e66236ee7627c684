// Speed of the core pipeline on the built-in body (docs/performance.md):
//   rest vertices for a β, training the four presets, measurements → .glb bytes, the map estimator,
//   measuring, volume and a section, the volume polynomial, the self-intersection check.
#include <benchmark/benchmark.h>

#include "caliper/caliper.h"

using namespace caliper;

namespace {

std::shared_ptr<const BodyModel> female_model() {
  static auto model = std::make_shared<const BodyModel>(load_model("mannequin", Sex::Female));
  return model;
}

std::map<std::string, double> typical_inputs() {
  return measurements_from_edge({{"stature", 165}, {"weight", 62}, {"span", 167}, {"crotch_height", 77},
                                 {"hip_breadth", 36}, {"arm_length", 55}});
}

void BM_RestVertices(benchmark::State& state) {
  const auto model = female_model();
  Eigen::VectorXd beta = Eigen::VectorXd::LinSpaced(model->shape_count(), -1.0, 1.0);
  Vertices out;
  for (auto _ : state) {
    model->rest_vertices(beta, out);
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["vertices"] = model->vertex_count();
}
BENCHMARK(BM_RestVertices)->Unit(benchmark::kMicrosecond);

void BM_TrainFourPresets(benchmark::State& state) {
  const auto model = female_model();
  for (auto _ : state) {
    AvatarBuilder builder(model);  // fresh: nothing cached
    for (const auto& p : preset_names()) benchmark::DoNotOptimize(builder.regressor(p, preset_inputs(p)).get());
  }
}
BENCHMARK(BM_TrainFourPresets)->Unit(benchmark::kMillisecond);

void BM_MeasurementsToGlb(benchmark::State& state) {
  const auto model = female_model();
  AvatarBuilder builder(model);
  AvatarRequest req;
  req.measurements = typical_inputs();
  req.regressor = "R5";
  builder.build(req);  // train once: the server keeps its builders
  req.measure_avatar = state.range(0) != 0;  // 0: measurements → β → body → GLB bytes; 1: also measure all
  for (auto _ : state) {
    const Avatar a = builder.build(req);
    std::string glb = write_glb(*model, a.rest_vertices);
    benchmark::DoNotOptimize(glb.data());
  }
}
BENCHMARK(BM_MeasurementsToGlb)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// The default estimator, auto: Levenberg–Marquardt on exact Jacobians (vertex
// gradients times S) on the six inputs, kept inside the population. Arg 0: β and its covariance
// only; 1: also the SD of all 43 measurements and of every vertex, and the avatar measured (what
// `caliper avatar` and the server do). Second arg: 0 "exact" noise (the default), 1 "self".
void BM_MapEstimate(benchmark::State& state) {
  const auto model = female_model();
  AvatarBuilder builder(model);
  AvatarRequest req;
  req.measurements = typical_inputs();
  req.regressor = "auto";
  req.noise = state.range(1) != 0 ? "self" : "exact";
  req.measure_avatar = state.range(0) != 0;
  req.vertex_uncertainty = state.range(0) != 0;
  builder.build(req);  // what is worked out once per model (the server keeps its builders)
  int inputs = 0;
  for (auto _ : state) {
    const Avatar a = builder.build(req);
    benchmark::DoNotOptimize(a.beta.data());
    inputs = static_cast<int>(a.input_fits.size());
  }
  state.counters["inputs"] = inputs;
}
BENCHMARK(BM_MapEstimate)->Args({0, 0})->Args({1, 0})->Args({0, 1})->Args({1, 1})->Unit(benchmark::kMillisecond);

void BM_MeasureAll(benchmark::State& state) {
  const auto model = female_model();
  const Vertices rest = model->rest_vertices(Eigen::VectorXd::Zero(model->shape_count()));
  for (auto _ : state) benchmark::DoNotOptimize(measure_all(*model, rest));
}
BENCHMARK(BM_MeasureAll)->Unit(benchmark::kMillisecond);

}  // namespace



namespace {
void BM_VolumeAndSection(benchmark::State& state) {
  const auto model = female_model();
  const Vertices rest = model->rest_vertices(Eigen::VectorXd::Zero(model->shape_count()));
  const auto* hip = model->find_measurement(state.range(0) ? "hip_breadth" : "stature");
  for (auto _ : state) {
    if (state.range(0)) benchmark::DoNotOptimize(measure(*model, *hip, rest));
    else benchmark::DoNotOptimize(signed_volume(rest, model->faces()));
  }
  state.SetLabel(state.range(0) ? "hip_breadth section" : "volume");
}
BENCHMARK(BM_VolumeAndSection)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

// The volume as a cubic in β (VolumePolynomial): worked out once per model, on the estimator's
// first use; then each evaluation with its gradient, as every estimator step takes it.
void BM_VolumePolynomial(benchmark::State& state) {
  const auto model = female_model();
  if (state.range(0) == 0) {
    for (auto _ : state) benchmark::DoNotOptimize(VolumePolynomial(*model).shape_count());
    state.SetLabel("built");
    return;
  }
  const VolumePolynomial poly(*model);
  const Eigen::VectorXd beta = Eigen::VectorXd::LinSpaced(model->shape_count(), -1.0, 1.0);
  Eigen::RowVectorXd gradient;
  for (auto _ : state) benchmark::DoNotOptimize(poly.value(beta, &gradient));
  state.SetLabel("value and gradient");
}
BENCHMARK(BM_VolumePolynomial)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

// The self-intersection check the tests run on every generated and posed body.
void BM_SelfIntersections(benchmark::State& state) {
  const auto model = female_model();
  const Vertices rest = model->rest_vertices(Eigen::VectorXd::Zero(model->shape_count()));
  for (auto _ : state) benchmark::DoNotOptimize(self_intersections(rest, model->faces()));
  state.counters["faces"] = static_cast<double>(model->faces().rows());
}
BENCHMARK(BM_SelfIntersections)->Unit(benchmark::kMillisecond);
}  // namespace
BENCHMARK_MAIN();
