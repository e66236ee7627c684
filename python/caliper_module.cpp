// The Python module `caliper` (docs/python.md): the public C++ API (include/caliper/) for NumPy
// users, with no logic of its own. Each function makes the same library calls as the `caliper`
// command line, so a script and the CLI give identical avatars for identical inputs. Long calls
// release the GIL, so threads building avatars run in parallel.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <optional>

#include "caliper/caliper.h"
#include "caliper/evaluation/evaluate.h"
#include "caliper/io/ansur.h"

namespace py = pybind11;
using namespace caliper;

namespace {

// ---- Errors: caliper::Error → a Python class per ErrorKind ------------------------------------

struct ErrorClasses {
  py::object base, invalid_argument, out_of_range, suspect_input, io, format, unsupported;
  py::object for_error(const Error& e) const {
    if (dynamic_cast<const SuspectInputError*>(&e)) return suspect_input;
    return for_kind(e.kind());
  }
  py::object for_kind(ErrorKind kind) const {
    switch (kind) {
      case ErrorKind::InvalidArgument: return invalid_argument;
      case ErrorKind::OutOfRange: return out_of_range;
      case ErrorKind::Io: return io;
      case ErrorKind::Format: return format;
      case ErrorKind::Unsupported: return unsupported;
    }
    return base;
  }
};
// Set once at import and never freed: a static's destructor would drop references after the
// interpreter has finalised.
ErrorClasses* error_classes = nullptr;

py::object new_error_class(py::module_& m, const char* name, py::handle bases, const char* doc) {
  const std::string qualified = std::string("caliper.") + name;
  py::object cls = py::reinterpret_steal<py::object>(
      PyErr_NewExceptionWithDoc(qualified.c_str(), doc, bases.ptr(), nullptr));
  if (!cls) throw py::error_already_set();
  m.add_object(name, cls);
  return cls;
}

// Raises the Python twin of `e`: message, kind, field, origin, and the catalogue's accepted range
// (lo, hi, unit) when the field is a measurement.
void raise_python_error(const Error& e) {
  py::object cls = error_classes->for_error(e);
  py::object error = cls(e.what());
  error.attr("kind") = to_string(e.kind());
  error.attr("field") = e.field();
  error.attr("origin") = to_string(e.origin());
  py::object range = py::none();
  if (const MeasurementInfo* info = find_measurement_info(e.field()))
    range = py::make_tuple(info->min_edge, info->max_edge, edge_unit(*info));
  error.attr("accepted_range") = range;
  PyErr_SetObject(cls.ptr(), error.ptr());
}

void register_errors(py::module_& m) {
  ErrorClasses& classes = *new ErrorClasses;
  classes.base = new_error_class(m, "Error", PyExc_Exception,
                                 "A Caliper error. Attributes: kind, field (the offending measurement, argument or "
                                 "array, or ''), origin ('caller' or 'installation'), accepted_range ((lo, hi, "
                                 "unit) in cm or kg when field is a measurement, else None).");
  const py::tuple value_bases = py::make_tuple(classes.base, py::handle(PyExc_ValueError));
  classes.invalid_argument = new_error_class(m, "InvalidArgumentError", value_bases,
                                             "A value is NaN, negative, absurd or of the wrong kind.");
  classes.out_of_range = new_error_class(m, "OutOfRangeError", py::make_tuple(classes.invalid_argument),
                                         "A measurement outside its accepted range (see accepted_range).");
  classes.suspect_input = new_error_class(
      m, "SuspectInputError", py::make_tuple(classes.invalid_argument),
      "Values that look swapped or in the wrong unit (e.g. stature_cm=1.65); the message says what was probably "
      "meant; force=True builds with them as given.");
  classes.io = new_error_class(m, "IoError", py::make_tuple(classes.base, py::handle(PyExc_OSError)),
                               "A file cannot be opened, read or written.");
  classes.format = new_error_class(m, "FormatError", value_bases,
                                   "A file or array is malformed, truncated or inconsistent.");
  classes.unsupported = new_error_class(m, "UnsupportedError", py::make_tuple(classes.base),
                                        "A valid request Caliper cannot serve (e.g. a measurement the model lacks).");
  error_classes = &classes;
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const Error& e) {
      raise_python_error(e);
    }
  });
}

// ---- Models and avatars ----------------------------------------------------------------------

// A loaded model and its avatar builder (which trains and keeps regressors), shared by every
// avatar built from it.
struct Model {
  std::shared_ptr<const BodyModel> body;
  std::shared_ptr<const AvatarBuilder> builder;
};

Model load(const std::string& name_or_path, const std::string& sex) {
  const Sex parsed = parse_sex(sex);
  py::gil_scoped_release release;
  auto body = std::make_shared<const BodyModel>(load_model(name_or_path, parsed));
  return Model{body, std::make_shared<const AvatarBuilder>(body)};
}

struct PyAvatar {
  Model model;
  Avatar avatar;
};

// The measurements as the CLI takes them: canonical names or aliases → cm or kg.
std::map<std::string, double> edge_values(const py::kwargs& named, const std::optional<std::map<std::string, double>>& more) {
  std::map<std::string, double> edge;
  // Aliases of one measurement (height, stature) are caught by avatar_request_from_edge.
  const auto add = [&edge](const std::string& name, double value) {
    if (!edge.emplace(name, value).second) throw Error(ErrorKind::InvalidArgument, name + " is given twice", name);
  };
  for (const auto& [name, value] : more.value_or(std::map<std::string, double>{})) add(name, value);
  for (const auto& [key, value] : named) {
    const std::string argument = py::str(key);
    // stature_cm=…, weight_kg=…: the unit is part of the argument's name and must be the
    // catalogue's, so weight_cm=60 is refused instead of read as kilograms.
    const std::string name = argument.size() > 3 ? argument.substr(0, argument.size() - 3) : argument;
    const std::string unit = argument.size() > 3 ? argument.substr(argument.size() - 2) : "";
    const MeasurementInfo* info = find_measurement_info(name);
    if (argument.size() <= 3 || argument[argument.size() - 3] != '_' || !info)
      throw Error(ErrorKind::InvalidArgument,
                  "unknown argument '" + argument + "': measurements are NAME_cm or NAME_kg with a canonical name or "
                  "alias of the catalogue (`caliper avatar --help`, docs/cli.md), or measurements={name: value}",
                  argument);
    if (unit != edge_unit(*info))
      throw Error(ErrorKind::InvalidArgument,
                  "'" + argument + "': " + info->name + " is given in " + edge_unit(*info) + ", as " + name + "_" +
                      edge_unit(*info), info->name);
    if (value.is_none()) continue;
    if (!py::isinstance<py::float_>(value) && !py::isinstance<py::int_>(value))
      throw Error(ErrorKind::InvalidArgument, info->name + " must be a number (" + edge_unit(*info) + ")", info->name);
    add(name, value.cast<double>());
  }
  return edge;
}

PyAvatar build(const Model& model, const AvatarRequest& request) {
  py::gil_scoped_release release;
  return PyAvatar{model, model.builder->build(request)};
}

// `model` is a Model or a name/path loaded for `sex`.
Model model_argument(const py::object& model, const std::optional<std::string>& sex) {
  if (py::isinstance<Model>(model)) {
    const Model& m = model.cast<const Model&>();
    if (sex && parse_sex(*sex) != m.body->sex())
      throw Error(ErrorKind::InvalidArgument,
                  "sex='" + *sex + "' differs from the given model's (" + to_string(m.body->sex()) + ")", "sex");
    return m;
  }
  if (!py::isinstance<py::str>(model))
    throw Error(ErrorKind::InvalidArgument, "model must be a caliper.Model or a model name or .npz path", "model");
  return load(model.cast<std::string>(), sex.value_or("female"));
}

py::object report_dict(const PyAvatar& a) {
  return py::module_::import("json").attr("loads")(avatar_report_json(*a.model.body, a.avatar));
}

// ---- Measuring arrays ------------------------------------------------------------------------

Vertices vertices_argument(const py::array_t<double, py::array::c_style | py::array::forcecast>& array) {
  if (array.ndim() != 2 || array.shape(1) != 3)
    throw Error(ErrorKind::Format, "vertices must be an N×3 array (metres)", "vertices");
  Vertices v = Eigen::Map<const Vertices>(array.data(), array.shape(0), 3);
  if (!v.allFinite()) throw Error(ErrorKind::InvalidArgument, "vertices hold NaN or infinite values", "vertices");
  return v;
}

Faces faces_argument(const py::array& array, Eigen::Index vertex_count) {
  if (array.dtype().kind() != 'i' && array.dtype().kind() != 'u')
    throw Error(ErrorKind::Format, "faces must be an integer array, got dtype " + std::string(py::str(array.dtype())),
                "faces");
  const auto indices = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(array);
  if (indices.ndim() != 2 || indices.shape(1) != 3)
    throw Error(ErrorKind::Format, "faces must be an M×3 array of vertex indices", "faces");
  Faces f(indices.shape(0), 3);
  for (py::ssize_t i = 0; i < indices.shape(0); ++i)
    for (py::ssize_t c = 0; c < 3; ++c) {
      const std::int64_t index = indices.at(i, c);
      if (index < 0 || index >= vertex_count)
        throw Error(ErrorKind::Format, "faces[" + std::to_string(i) + "] refers to vertex " + std::to_string(index) +
                                           ", outside [0, " + std::to_string(vertex_count - 1) + "]", "faces");
      f(i, c) = static_cast<std::int32_t>(index);
    }
  return f;
}

// Every measurement the model defines when the mesh has the model's topology; otherwise what a
// bare closed mesh gives (stature, volume, weight by the model's volume → weight fit).
std::map<std::string, double> measure_arrays(const py::array_t<double, py::array::c_style | py::array::forcecast>& vertices,
                                             const py::array& faces, const py::object& model,
                                             const std::optional<std::string>& sex) {
  const Model m = model_argument(model, sex);
  Mesh mesh{vertices_argument(vertices), {}};
  mesh.faces = faces_argument(faces, mesh.vertices.rows());
  py::gil_scoped_release release;
  return measure_person(*m.body, mesh, "vertices");
}


// ---- Posing, plausibility, evaluation --------------------------------------------------------

// An SMPL-style pose as any array of axis-angle values (radians): 24×3 or 72 (SMPL), 52×3 or 156
// (SMPL-H), 54×3 or 162 (the built-in rig), or J×3 of the model's own joints (pose.h).
Pose pose_argument(const BodyModel& model, const py::array_t<double, py::array::c_style | py::array::forcecast>& values) {
  if (values.ndim() > 2 || (values.ndim() == 2 && values.shape(1) != 3))
    throw Error(ErrorKind::InvalidArgument, "pose must be a flat array of axis-angle values or a J×3 array (radians)",
                "pose");
  return pose_from_axis_angles(model, std::vector<double>(values.data(), values.data() + values.size()));
}

// Posed vertices (N×3) and joints (J×3), metres.
std::pair<Vertices, Eigen::MatrixX3d> pose_avatar(const PyAvatar& a,
                                                  const py::array_t<double, py::array::c_style | py::array::forcecast>& values) {
  const BodyModel& model = *a.model.body;
  const Pose pose = pose_argument(model, values);
  py::gil_scoped_release release;
  return {pose_vertices(model, a.avatar.rest_vertices, pose), posed_joints(model, a.avatar.joints, pose)};
}

py::dict plausibility_dict(const Plausibility& p) {
  py::list per_value;
  for (Verdict v : p.per_value) per_value.append(to_string(v));
  py::dict d;
  d["verdict"] = to_string(p.overall);
  d["per_value"] = per_value;
  d["mahalanobis_sq"] = p.mahalanobis_sq;
  d["tail_probability"] = p.tail_probability;
  d["rarity"] = p.rarity;
  d["population"] = p.population;
  d["drivers"] = p.drivers;
  d["explanation"] = p.explanation;
  return d;
}

py::dict input_fits_dict(const std::map<std::string, MapInputFit>& fits) {
  py::dict d;
  for (const auto& [name, f] : fits) {
    py::dict fit;
    fit["value"] = f.value;
    fit["noise_sd"] = f.noise_sd;
    fit["effective_sd"] = f.effective_sd;
    fit["fitted"] = f.fitted;
    fit["expected"] = f.expected;
    fit["expected_sd"] = f.expected_sd;
    fit["z"] = f.z;
    fit["population_mean"] = f.population_mean;
    fit["population_sd"] = f.population_sd;
    fit["population_z"] = f.population_z;
    d[py::str(name)] = fit;
  }
  return d;
}

// `caliper eval --json` as a dict: avatars of the people in an ANSUR II-format CSV against their
// measurements, per estimator. One avatar builder per sex, kept for the whole evaluation.
py::object evaluate_csv(const std::string& subjects_path, const std::vector<std::string>& estimators,
                        const std::string& noise, const std::string& map_noise, std::uint64_t seed,
                        const std::string& model, const std::optional<std::string>& train, int threads) {
  if (threads < 1 || threads > 256)
    throw Error(ErrorKind::OutOfRange, "threads must be in [1, 256], got " + std::to_string(threads), "threads");
  EvaluationOptions options;
  options.regressors = estimators;
  options.noise = parse_noise(noise);
  options.map_noise = map_noise;
  options.seed = seed;
  options.threads = threads;
  std::string json;
  {
    py::gil_scoped_release release;
    const std::vector<AnsurSubject> subjects = read_ansur_csv(subjects_path);
    if (subjects.empty()) throw Error(ErrorKind::Format, "'" + subjects_path + "' has no subjects", "subjects");
    std::vector<AnsurSubject> training;
    if (train) {
      training = read_ansur_csv(*train);
      options.linear_training = &training;
    }
    std::map<Sex, std::shared_ptr<const AvatarBuilder>> builders;
    const auto builder_for = [&](Sex sex) {
      auto& b = builders[sex];
      if (!b) b = std::make_shared<const AvatarBuilder>(std::make_shared<const BodyModel>(load_model(model, sex)));
      return b;
    };
    json = evaluation_json(evaluate_subjects(subjects, builder_for, options));
  }
  return py::module_::import("json").attr("loads")(json);
}

}  // namespace

PYBIND11_MODULE(_caliper, m) {
  m.doc() = "Caliper: metrically accurate, rigged 3-D avatars from a few body measurements (docs/python.md). "
            "Arrays are NumPy, lengths in metres; arguments named *_cm / *_kg are in centimetres / kilograms.";
  m.attr("__version__") = CALIPER_VERSION;
  register_errors(m);

  py::class_<Model>(m, "Model", "A body model: template, shape space, rig, landmarks and measurement definitions.")
      .def_property_readonly("name", [](const Model& s) { return s.body->name(); })
      .def_property_readonly("sex", [](const Model& s) { return std::string(to_string(s.body->sex())); })
      .def_property_readonly("vertex_count", [](const Model& s) { return s.body->vertex_count(); })
      .def_property_readonly("shape_count", [](const Model& s) { return s.body->shape_count(); })
      .def_property_readonly("joint_names", [](const Model& s) { return s.body->data().joint_names; })
      .def_property_readonly(
          "faces", [](const Model& s) -> const Faces& { return s.body->faces(); }, py::return_value_policy::reference_internal,
          "M×3 int32 vertex indices, counter-clockwise seen from outside (read-only view)")
      .def_property_readonly(
          "template_vertices", [](const Model& s) -> const Vertices& { return s.body->data().template_vertices; },
          py::return_value_policy::reference_internal, "N×3 float64 mean rest shape, metres (read-only view)")
      .def_property_readonly("parents", [](const Model& s) { return s.body->data().parents; },
                             "J parent joint indices (-1 for the root), in joint_names' order")
      .def_property_readonly(
          "skin_weights", [](const Model& s) { return Eigen::MatrixXd(s.body->data().skin_weights); },
          "N×J float64 linear-blend-skinning weights, dense (a new array; rows sum to 1, columns in joint_names' order; "
          "most rows have at most 4 non-zero weights, the influences the exported files keep)")
      .def("__repr__", [](const Model& s) { return "<caliper.Model " + s.body->name() + ">"; });

  py::class_<PyAvatar>(m, "Avatar", "An avatar built from measurements; arrays are read-only views, metres.")
      .def_property_readonly(
          "vertices", [](const PyAvatar& a) -> const Vertices& { return a.avatar.rest_vertices; },
          py::return_value_policy::reference_internal, "N×3 float64 rest-pose (T-pose) vertices, metres, +Y up")
      .def_property_readonly(
          "faces", [](const PyAvatar& a) -> const Faces& { return a.model.body->faces(); },
          py::return_value_policy::reference_internal, "M×3 int32 vertex indices")
      .def_property_readonly(
          "joints", [](const PyAvatar& a) -> const Eigen::MatrixX3d& { return a.avatar.joints; },
          py::return_value_policy::reference_internal, "J×3 float64 joint positions, metres (order: model.joint_names)")
      .def_property_readonly(
          "beta", [](const PyAvatar& a) -> const Eigen::VectorXd& { return a.avatar.beta; },
          py::return_value_policy::reference_internal, "K float64 shape values (SD from the mean body)")
      .def_property_readonly(
          "vertex_sd", [](const PyAvatar& a) -> const Eigen::VectorXd& { return a.avatar.vertex_sd; },
          py::return_value_policy::reference_internal, "N float64 posterior SD per vertex, metres (estimator map/auto; else empty)")
      .def_property_readonly("model", [](const PyAvatar& a) { return a.model; })
      .def_property_readonly("plausibility", [](const PyAvatar& a) { return plausibility_dict(a.avatar.plausibility); },
                             "dict: verdict (plausible | unusual | implausible), per_value (one verdict per beta), "
                             "mahalanobis_sq, tail_probability, rarity, population, drivers, explanation")
      .def_property_readonly("uncertainty", [](const PyAvatar& a) { return a.avatar.uncertainty; },
                             "posterior SD of every measurement by canonical name, SI (metres, kg), rest pose; "
                             "estimator map/auto only, else empty")
      .def_property_readonly(
          "beta_covariance", [](const PyAvatar& a) -> const Eigen::MatrixXd& { return a.avatar.beta_covariance; },
          py::return_value_policy::reference_internal, "K×K float64 posterior covariance of beta (map/auto; else 0×0)")
      .def_property_readonly("input_fits", [](const PyAvatar& a) { return input_fits_dict(a.avatar.input_fits); },
                             "map/auto: per input, how it fitted (value, noise_sd, fitted, expected, z, population_z, "
                             "…; SI)")
      .def_property_readonly("noise", [](const PyAvatar& a) { return a.avatar.noise; },
                             "the noise setting map/auto used (exact, self, other); '' for the paper's regressors")
      .def_property_readonly("requested", [](const PyAvatar& a) { return a.avatar.requested; },
                             "the measurements given, by canonical name, SI (metres, kg)")
      .def_property_readonly("skin_weights", [](const PyAvatar& a) { return Eigen::MatrixXd(a.model.body->data().skin_weights); },
                             "N×J float64 skinning weights, dense: the model's (Model.skin_weights)")
      .def("pose", &pose_avatar, py::arg("pose"),
           "pose(pose) -> (vertices N×3, joints J×3), metres: the avatar posed by linear blend skinning. pose: SMPL-style "
           "axis-angle values in radians, one rotation per joint relative to its parent (joint 0's is the global "
           "orientation): 72 values or 24×3 (SMPL), 156 or 52×3 (SMPL-H), 162 or 54×3 (the built-in rig with fingers), "
           "or J×3 of this model's joints; joints not covered stay at rest.")
      .def_property_readonly("estimator", [](const PyAvatar& a) { return a.avatar.regressor; })
      .def_property_readonly("warnings", [](const PyAvatar& a) { return a.avatar.warnings; })
      .def_property_readonly("achieved", [](const PyAvatar& a) { return a.avatar.achieved; },
                             "every measurement of the avatar by canonical name, SI (metres, kg)")
      .def_property_readonly("report", &report_dict,
                             "the JSON report of `caliper avatar --report` as a dict (cm and kg, as the CLI)")
      .def(
          "save",
          [](const PyAvatar& a, const std::string& path, const std::string& skeleton, bool morphs) {
            AvatarFileOptions options;
            options.skeleton = parse_skeleton_naming(skeleton, "skeleton");
            options.morphs = morphs;
            py::gil_scoped_release release;
            save_avatar(path, *a.model.body, a.avatar, "path", options);
          },
          py::arg("path"), py::kw_only(), py::arg("skeleton") = "smpl", py::arg("morphs") = false,
          "save(path, *, skeleton='smpl', morphs=False): writes path.glb (rigged glTF 2.0 binary), .vrm (VRM 1.0), "
          ".fbx (binary FBX 7.4, centimetres) or .obj (metres), as `caliper avatar -o`. skeleton: bone names, smpl (the model's) or "
          "humanoid (Unity Humanoid); morphs: .glb/.vrm/.fbx also carry the shape directions as morph targets.")
      .def("__repr__", [](const PyAvatar& a) {
        return "<caliper.Avatar model " + a.model.body->name() + ", estimator " + a.avatar.regressor + ">";
      });

  m.def("load_model", &load, py::arg("name_or_path"), py::arg("sex") = "female",
        "Loads a model by name (mannequin, makehuman, … in the models folder; the sex picks the variant) or from "
        "a native or SMPL .npz path.");
  m.def(
      "build_avatar",
      [](std::optional<std::string> sex, std::optional<std::map<std::string, double>> measurements,
         const std::string& estimator, const std::string& noise, std::optional<std::map<std::string, double>> noise_sd,
         std::optional<std::string> real_to_virtual, const py::object& model, bool force, const py::kwargs& named) {
        EdgeAvatarRequest edge;
        edge.measurements = edge_values(named, measurements);
        edge.estimator = estimator;
        edge.noise = noise;
        edge.noise_sd = noise_sd.value_or(std::map<std::string, double>{});
        if (real_to_virtual) edge.maps = RealToVirtual::load(*real_to_virtual);
        edge.force = force;
        const AvatarRequest request = avatar_request_from_edge(edge);  // checked before a model is loaded
        return build(model_argument(model, sex), request);
      },
      py::kw_only(), py::arg("sex") = py::none(), py::arg("measurements") = py::none(), py::arg("estimator") = "auto",
      py::arg("noise") = "exact", py::arg("noise_sd") = py::none(), py::arg("real_to_virtual") = py::none(),
      py::arg("model") = "mannequin", py::arg("force") = false,
      "build_avatar(*, sex='female', stature_cm=…, weight_kg=…, span_cm=None, crotch_height_cm=None, …, "
      "measurements=None, estimator='auto', noise='exact', noise_sd=None, real_to_virtual=None, model='mannequin', "
      "force=False) -> Avatar\n\n"
      "Measurements are keyword arguments NAME_cm / NAME_kg (any canonical name or alias; None is skipped) or a dict "
      "measurements={name: cm or kg}. estimator: auto (= map), R2, R4, R5, R6 or 'custom:a,b'. noise (auto/map): "
      "exact, self or other; noise_sd: {name: SD in cm or kg} overriding it per measurement (as --noise-sd). "
      "real_to_virtual: a map file of `caliper map fit` applied instead of the model's own (as --map). model: a "
      "caliper.Model or a name/path. force: build even when values look swapped or "
      "in the wrong unit (otherwise InvalidArgumentError naming the field).");
  m.def("evaluate", &evaluate_csv, py::arg("subjects"), py::kw_only(),
        py::arg("estimators") = std::vector<std::string>{"R2", "R4", "R5", "R6", "auto"}, py::arg("noise") = "none",
        py::arg("map_noise") = "", py::arg("seed") = 1, py::arg("model") = "mannequin", py::arg("train") = py::none(),
        py::arg("threads") = 2,
        "evaluate(subjects, *, estimators=('R2','R4','R5','R6','auto'), noise='none', map_noise='', seed=1, "
        "model='mannequin', train=None, threads=2) -> dict\n\n"
        "`caliper eval --json` as a dict: avatars of every person of an ANSUR II-format CSV (subjects; both sexes may "
        "be mixed) from their Virtual Caliper inputs, against what was measured on them, per estimator "
        "(docs/evaluation.md). noise: simulated measurement noise none, self or other (paper Table 2), drawn with "
        "seed; map_noise: what auto/map assumes (exact, self, other; '' = as noise); train: an ANSUR II-format CSV "
        "the linear limit is fitted on (else 10-fold cross-validation). Lengths in cm, weights in kg.");
  m.def("measure", &measure_arrays, py::arg("vertices"), py::arg("faces"), py::kw_only(),
        py::arg("model") = "mannequin", py::arg("sex") = py::none(),
        "measure(vertices (N×3, metres), faces (M×3 int), *, model='mannequin', sex=None) -> dict\n\n"
        "With the model's topology (same vertex count and faces): every measurement the model defines, by "
        "canonical name, SI (metres, kg). Any other closed mesh: stature (m), volume (m³) and weight (kg, by the "
        "model's volume → weight fit).");
}
