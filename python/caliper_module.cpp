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

namespace py = pybind11;
using namespace caliper;

namespace {

// ---- Errors: caliper::Error → a Python class per ErrorKind ------------------------------------

struct ErrorClasses {
  py::object base, invalid_argument, out_of_range, io, format, unsupported;
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
  py::object cls = error_classes->for_kind(e.kind());
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
  const auto add = [&edge](const std::string& name, double value) {
    const MeasurementInfo* info = find_measurement_info(name);
    const std::string canonical = info ? info->name : name;  // unknown: measurements_from_edge names it
    if (!edge.emplace(canonical, value).second)
      throw Error(ErrorKind::InvalidArgument, canonical + " is given twice", canonical);
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
    add(info->name, value.cast<double>());
  }
  return edge;
}

PyAvatar build(const Model& model, const std::map<std::string, double>& edge, const std::string& estimator,
               const std::string& noise, bool force) {
  if (edge.empty())
    throw Error(ErrorKind::InvalidArgument,
                "no measurements given: give at least stature_cm and weight_kg (e.g. stature_cm=165, weight_kg=62)",
                "measurements");
  // Typing mistakes (swapped, wrong unit) are refused before anything is built, as in the CLI.
  if (!force)
    if (const auto suspects = suspect_input_mistakes(edge); !suspects.empty())
      throw Error(ErrorKind::InvalidArgument, describe_suspects(suspects), suspects.front().field);
  AvatarRequest request;
  request.measurements = measurements_from_edge(edge);
  request.regressor = estimator;
  request.noise = noise;
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
  const Faces& own = m.body->faces();
  if (mesh.vertices.rows() == m.body->vertex_count() && mesh.faces.rows() == own.rows() && mesh.faces == own)
    return measure_all(*m.body, mesh.vertices);
  const MeshMeasurements mm = measure_mesh(mesh, m.body->data().weight_from_volume);
  return {{"stature", mm.stature}, {"volume", mm.volume}, {"weight", mm.weight}};
}

}  // namespace

PYBIND11_MODULE(caliper, m) {
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
      .def_property_readonly("estimator", [](const PyAvatar& a) { return a.avatar.regressor; })
      .def_property_readonly("warnings", [](const PyAvatar& a) { return a.avatar.warnings; })
      .def_property_readonly("achieved", [](const PyAvatar& a) { return a.avatar.achieved; },
                             "every measurement of the avatar by canonical name, SI (metres, kg)")
      .def_property_readonly("report", &report_dict,
                             "the JSON report of `caliper avatar --report` as a dict (cm and kg, as the CLI)")
      .def(
          "save",
          [](const PyAvatar& a, const std::string& path) {
            py::gil_scoped_release release;
            save_avatar(path, *a.model.body, a.avatar);
          },
          py::arg("path"), "Writes path.glb (rigged glTF 2.0 binary), .vrm (VRM 1.0), .fbx (binary FBX 7.4) or .obj (metres), as `caliper avatar -o`.")
      .def("__repr__", [](const PyAvatar& a) {
        return "<caliper.Avatar model " + a.model.body->name() + ", estimator " + a.avatar.regressor + ">";
      });

  m.def("load_model", &load, py::arg("name_or_path"), py::arg("sex") = "female",
        "Loads a model by name (mannequin, makehuman, … in the models folder; the sex picks the variant) or from "
        "a native or SMPL .npz path.");
  m.def(
      "build_avatar",
      [](std::optional<std::string> sex, std::optional<std::map<std::string, double>> measurements,
         const std::string& estimator, const std::string& noise, const py::object& model, bool force,
         const py::kwargs& named) {
        const std::map<std::string, double> edge = edge_values(named, measurements);
        return build(model_argument(model, sex), edge, estimator, noise, force);
      },
      py::kw_only(), py::arg("sex") = py::none(), py::arg("measurements") = py::none(), py::arg("estimator") = "auto",
      py::arg("noise") = "exact", py::arg("model") = "mannequin", py::arg("force") = false,
      "build_avatar(*, sex='female', stature_cm=…, weight_kg=…, span_cm=None, crotch_height_cm=None, …, "
      "measurements=None, estimator='auto', noise='exact', model='mannequin', force=False) -> Avatar\n\n"
      "Measurements are keyword arguments NAME_cm / NAME_kg (any canonical name or alias; None is skipped) or a dict "
      "measurements={name: cm or kg}. estimator: auto (= map), R2, R4, R5, R6 or 'custom:a,b'. noise (auto/map): "
      "exact, self or other. model: a caliper.Model or a name/path. force: build even when values look swapped or "
      "in the wrong unit (otherwise InvalidArgumentError naming the field).");
  m.def("measure", &measure_arrays, py::arg("vertices"), py::arg("faces"), py::kw_only(),
        py::arg("model") = "mannequin", py::arg("sex") = py::none(),
        "measure(vertices (N×3, metres), faces (M×3 int), *, model='mannequin', sex=None) -> dict\n\n"
        "With the model's topology (same vertex count and faces): every measurement the model defines, by "
        "canonical name, SI (metres, kg). Any other closed mesh: stature (m), volume (m³) and weight (kg, by the "
        "model's volume → weight fit).");
}
