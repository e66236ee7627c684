// FBX binary 7.4 writer for a rigged avatar.
//
// The binary layout (public: Autodesk's FBX SDK documentation and Blender's format notes): a
// 27-byte header ("Kaydara FBX Binary  \0", 0x1A 0x00, uint32 version), then node records.
// A record is uint32 end offset (absolute), uint32 property count, uint32 property bytes, uint8
// name length, the name, its properties, its child records, and a 13-byte zero record after the
// children (also written when a record has neither properties nor children); a zero record ends
// the top level. A property is a type code and its value: Y int16, C bool, I int32, F float,
// D double, L int64, S string and R raw (uint32 length first), and arrays i, l, f, d, b as uint32
// count, uint32 encoding (1 = zlib), uint32 byte length, then the (compressed) data.
// Integers are little-endian. Object names are "name\0\1Class".
//
// The scene: GlobalSettings declare +Y up, +Z front, +X side, right-handed, UnitScaleFactor 1:
// lengths are in centimetres, FBX's own unit (kFileUnitsPerMetre below says why); Objects hold the mesh Geometry (control points,
// triangles, per-vertex normals, per-corner UVs through an index as the model stores them), the
// mesh Model, a LimbNode Model (with a Skeleton NodeAttribute) per joint, a Material, a Skin
// deformer with one Cluster per joint (the vertex indices and weights, Transform = the joint's
// inverse bind matrix, TransformLink = its rest world matrix; the mesh sits at the origin), and
// a BindPose; Connections link them ("OO": child, parent; 0 is the scene root).
//
// Blend shapes (ExportOptions::morphs): a BlendShape Deformer on the mesh Geometry, and per shape
// direction k a BlendShapeChannel SubDeformer "shape_k" (DeformPercent 0, one target at
// FullWeights 100) holding a Geometry of class Shape "shape_k": Indexes (the control points it
// moves), Vertices and Normals (their displacement at 100 %, per listed point). Connections run
// shape → channel → blend shape → mesh geometry, as the FBX SDK's FbxShape / FbxBlendShapeChannel
// / FbxBlendShape objects are linked.
#include "caliper/export/fbx.h"

#include <zlib.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <vector>

#include "caliper/errors.h"
#include "export_common.h"

#ifndef CALIPER_VERSION
#define CALIPER_VERSION "unknown"
#endif

namespace caliper {

namespace {

constexpr std::uint32_t kFbxVersion = 7400;
// Lengths are written in centimetres. Unreal's FBX importer takes the numbers as centimetres
// unless "Convert Scene Unit" is ticked (it is not by default), while Unity ("Convert Units") and
// Blender ("Apply Unit") convert from the declared unit by default: only a centimetre file lands
// at its true size in all three without an import option.
constexpr double kFileUnitsPerMetre = 100.0;

struct Property {
  char type;
  std::string payload;  // the encoded value, after the type code
};

struct FbxNode {
  std::string name;
  std::vector<Property> properties;
  std::vector<FbxNode> children;

  FbxNode& add(FbxNode child) {
    children.push_back(std::move(child));
    return children.back();
  }
};

template <class T>
std::string raw_bytes(const T& value) {
  return std::string(reinterpret_cast<const char*>(&value), sizeof(T));
}

Property i32(std::int32_t v) { return {'I', raw_bytes(v)}; }
Property i64(std::int64_t v) { return {'L', raw_bytes(v)}; }
Property f64(double v) { return {'D', raw_bytes(v)}; }
Property text(const std::string& s) { return {'S', raw_bytes(static_cast<std::uint32_t>(s.size())) + s}; }

// An array property, zlib-compressed (FBX readers accept raw arrays too; compression keeps an
// avatar near a megabyte).
template <class T>
Property array(char type, const std::vector<T>& values) {
  const auto* data = reinterpret_cast<const Bytef*>(values.data());
  const uLong raw = static_cast<uLong>(values.size() * sizeof(T));
  uLongf packed = compressBound(raw);
  std::string out(packed, '\0');
  if (compress2(reinterpret_cast<Bytef*>(out.data()), &packed, data, raw, Z_DEFAULT_COMPRESSION) != Z_OK)
    throw Error(ErrorKind::Io, "FBX export: zlib could not compress an array", "fbx");
  out.resize(packed);
  return {type, raw_bytes(static_cast<std::uint32_t>(values.size())) + raw_bytes(std::uint32_t{1}) +
                    raw_bytes(static_cast<std::uint32_t>(out.size())) + out};
}
Property doubles(const std::vector<double>& v) { return array('d', v); }
Property ints(const std::vector<std::int32_t>& v) { return array('i', v); }

FbxNode node(std::string name, std::vector<Property> properties = {}, std::vector<FbxNode> children = {}) {
  return {std::move(name), std::move(properties), std::move(children)};
}

// A Properties70 entry: name, type, label, flags, then the values.
FbxNode p(const std::string& name, const std::string& type, const std::string& label, const std::string& flags,
          std::vector<Property> values) {
  std::vector<Property> props = {text(name), text(type), text(label), text(flags)};
  props.insert(props.end(), values.begin(), values.end());
  return node("P", std::move(props));
}

std::string object_name(const std::string& name, const std::string& cls) { return name + std::string("\0\1", 2) + cls; }

void serialise(const FbxNode& n, std::string& out) {
  const size_t start = out.size();
  std::string props;
  for (const Property& pr : n.properties) {
    props += pr.type;
    props += pr.payload;
  }
  out += raw_bytes(std::uint32_t{0});  // end offset, patched below
  out += raw_bytes(static_cast<std::uint32_t>(n.properties.size()));
  out += raw_bytes(static_cast<std::uint32_t>(props.size()));
  out += static_cast<char>(n.name.size());
  out += n.name;
  out += props;
  for (const FbxNode& c : n.children) serialise(c, out);
  if (!n.children.empty() || n.properties.empty()) out.append(13, '\0');
  const auto end = static_cast<std::uint32_t>(out.size());
  std::memcpy(out.data() + start, &end, 4);
}

std::vector<double> column_major(const Eigen::Matrix4d& m) {
  return std::vector<double>(m.data(), m.data() + 16);
}

Eigen::Matrix4d rest_world(const ExportRig& rig, int j) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = rig.orientations[static_cast<size_t>(j)];
  m.topRightCorner<3, 1>() = kFileUnitsPerMetre * rig.positions[static_cast<size_t>(j)];
  return m;
}

void check_fbx_inputs(const BodyModel& model, const Vertices& rest) {
  if (rest.rows() != model.vertex_count())
    throw Error(ErrorKind::InvalidArgument,
                "FBX export: " + std::to_string(rest.rows()) + " vertices given, model '" + model.name() + "' has " +
                    std::to_string(model.vertex_count()),
                "vertices");
  if (!rest.allFinite()) throw Error(ErrorKind::InvalidArgument, "FBX export: vertices contain NaN or infinity", "vertices");
}

class SceneBuilder {
 public:
  SceneBuilder(const BodyModel& model, const Vertices& rest, const ExportOptions& options)
      : model_(model), rest_(rest), options_(options), provenance_(options.provenance.value_or(model_provenance(model))) {}

  std::string bytes() {
    build_objects();
    std::string out = std::string("Kaydara FBX Binary  \0", 21) + "\x1a" + std::string(1, '\0') + raw_bytes(kFbxVersion);
    for (const FbxNode& n : {header_extension(), global_settings(), documents(), node("References"), definitions(),
                             objects_, connections_})
      serialise(n, out);
    out.append(13, '\0');
    return out;
  }

 private:
  std::int64_t new_id() { return next_id_++; }
  void connect(std::int64_t child, std::int64_t parent) { connections_.add(node("C", {text("OO"), i64(child), i64(parent)})); }

  FbxNode header_extension() const {
    const std::string notice = provenance_notice(provenance_);
    FbxNode meta = node("MetaData", {}, {node("Version", {i32(100)}), node("Title", {text(model_.name() + " avatar")}),
                                        node("Subject", {text("Caliper avatar, " + provenance_.sex)}),
                                        node("Author", {text("Caliper " + provenance_.caliper_version)}),
                                        node("Keywords", {text(provenance_.commercial_use ? "commercial use allowed" : "non-commercial")}),
                                        node("Revision", {text("")}), node("Comment", {text(notice)})});
    FbxNode info = node("SceneInfo", {text(object_name("GlobalInfo", "SceneInfo")), text("UserData")},
                        {node("Type", {text("UserData")}), node("Version", {i32(100)}), std::move(meta),
                         node("Properties70", {}, {p("Original|ApplicationVendor", "KString", "", "", {text("Caliper")}),
                                                   p("Original|ApplicationName", "KString", "", "", {text("Caliper")}),
                                                   p("Original|ApplicationVersion", "KString", "", "", {text(CALIPER_VERSION)})})});
    return node("FBXHeaderExtension", {},
                {node("FBXHeaderVersion", {i32(1003)}), node("FBXVersion", {i32(static_cast<std::int32_t>(kFbxVersion))}),
                 node("EncryptionType", {i32(0)}), node("Creator", {text(std::string("Caliper ") + CALIPER_VERSION)}),
                 std::move(info)});
  }

  static FbxNode global_settings() {
    auto axis = [](const char* name, int v) { return p(name, "int", "Integer", "", {i32(v)}); };
    return node("GlobalSettings", {},
                {node("Version", {i32(1000)}),
                 node("Properties70", {},
                      {axis("UpAxis", 1), axis("UpAxisSign", 1), axis("FrontAxis", 2), axis("FrontAxisSign", 1),
                       axis("CoordAxis", 0), axis("CoordAxisSign", 1), axis("OriginalUpAxis", 1), axis("OriginalUpAxisSign", 1),
                       p("UnitScaleFactor", "double", "Number", "", {f64(100.0 / kFileUnitsPerMetre)}),
                       p("OriginalUnitScaleFactor", "double", "Number", "", {f64(100.0 / kFileUnitsPerMetre)})})});
  }

  FbxNode documents() {
    return node("Documents", {},
                {node("Count", {i32(1)}),
                 node("Document", {i64(new_id()), text("Scene"), text("Scene")},
                      {node("Properties70", {}, {p("SourceObject", "object", "", "", {}),
                                                 p("ActiveAnimStackName", "KString", "", "", {text("")})}),
                       node("RootNode", {i64(0)})})});
  }

  FbxNode definitions() const {
    int total = 1;
    FbxNode defs = node("Definitions", {}, {node("Version", {i32(100)})});
    std::vector<FbxNode> types = {node("ObjectType", {text("GlobalSettings")}, {node("Count", {i32(1)})})};
    for (const auto& [type, count] : counts_) {
      types.push_back(node("ObjectType", {text(type)}, {node("Count", {i32(count)})}));
      total += count;
    }
    defs.add(node("Count", {i32(total)}));
    for (auto& t : types) defs.add(std::move(t));
    return defs;
  }

  void build_objects() {
    const std::int64_t mesh_model = new_id(), geometry = new_id(), material = new_id();
    objects_.add(geometry_node(geometry));
    objects_.add(mesh_model_node(mesh_model));
    objects_.add(material_node(material));
    connect(mesh_model, 0);
    connect(geometry, mesh_model);
    connect(material, mesh_model);
    counts_ = {{"Geometry", 1}, {"Model", 1}, {"Material", 1}};
    if (options_.morphs) add_blend_shapes(geometry);
    if (!options_.include_skin) return;
    const ExportRig rig = export_rig(model_, model_.joints(rest_), rest_, options_.skeleton);
    std::vector<std::int64_t> bone(static_cast<size_t>(rig.size()));
    for (auto& id : bone) id = new_id();
    for (int j = 0; j < rig.size(); ++j) {
      const std::int64_t attribute = new_id();
      objects_.add(limb_node(rig, j, bone[static_cast<size_t>(j)]));
      objects_.add(node("NodeAttribute", {i64(attribute), text(object_name(rig.names[static_cast<size_t>(j)], "NodeAttribute")), text("LimbNode")},
                        {node("TypeFlags", {text("Skeleton")})}));
      connect(attribute, bone[static_cast<size_t>(j)]);
      const int parent = rig.parents[static_cast<size_t>(j)];
      connect(bone[static_cast<size_t>(j)], parent < 0 ? 0 : bone[static_cast<size_t>(parent)]);
    }
    const std::int64_t skin = new_id();
    objects_.add(node("Deformer", {i64(skin), text(object_name("Skin", "Deformer")), text("Skin")},
                      {node("Version", {i32(101)}), node("Link_DeformAcuracy", {f64(50.0)})}));
    connect(skin, geometry);
    add_clusters(rig, bone, skin);
    add_bind_pose(rig, bone, mesh_model);
    counts_["Model"] += rig.size();
    counts_["NodeAttribute"] = rig.size();
    counts_["Deformer"] += 1 + rig.size();
    counts_["Pose"] = 1;
  }

  FbxNode geometry_node(std::int64_t id) const {
    const Faces& faces = model_.faces();
    std::vector<double> positions;
    positions.reserve(static_cast<size_t>(rest_.size()));
    for (Eigen::Index v = 0; v < rest_.rows(); ++v)
      for (int c = 0; c < 3; ++c) positions.push_back(kFileUnitsPerMetre * rest_(v, c));
    std::vector<std::int32_t> polygon;  // the last corner of a polygon is stored as −index − 1
    for (Eigen::Index f = 0; f < faces.rows(); ++f) polygon.insert(polygon.end(), {faces(f, 0), faces(f, 1), -faces(f, 2) - 1});
    const Vertices normals_d = vertex_normals(rest_, faces);
    std::vector<double> normals;
    for (Eigen::Index v = 0; v < normals_d.rows(); ++v)
      for (int c = 0; c < 3; ++c) normals.push_back(normals_d(v, c));
    FbxNode g = node("Geometry", {i64(id), text(object_name(options_.mesh_name, "Geometry")), text("Mesh")},
                     {node("Vertices", {doubles(positions)}), node("PolygonVertexIndex", {ints(polygon)}),
                      node("GeometryVersion", {i32(124)}),
                      node("LayerElementNormal", {i32(0)},
                           {node("Version", {i32(102)}), node("Name", {text("")}),
                            node("MappingInformationType", {text("ByVertice")}),
                            node("ReferenceInformationType", {text("Direct")}), node("Normals", {doubles(normals)})})});
    FbxNode layer = node("Layer", {i32(0)}, {node("Version", {i32(100)})});
    auto element = [](const char* type) { return node("LayerElement", {}, {node("Type", {text(type)}), node("TypedIndex", {i32(0)})}); };
    layer.add(element("LayerElementNormal"));
    if (model_.has_uvs()) {  // the model's own UV layout: one UV index per triangle corner
      const UvCoordinates& uv = model_.data().uv_coordinates;
      const Faces& uv_faces = model_.data().uv_faces;
      std::vector<double> uvs;
      for (Eigen::Index t = 0; t < uv.rows(); ++t) uvs.insert(uvs.end(), {uv(t, 0), uv(t, 1)});
      std::vector<std::int32_t> index;
      for (Eigen::Index f = 0; f < uv_faces.rows(); ++f) index.insert(index.end(), {uv_faces(f, 0), uv_faces(f, 1), uv_faces(f, 2)});
      g.add(node("LayerElementUV", {i32(0)},
                 {node("Version", {i32(101)}), node("Name", {text("UVMap")}),
                  node("MappingInformationType", {text("ByPolygonVertex")}),
                  node("ReferenceInformationType", {text("IndexToDirect")}), node("UV", {doubles(uvs)}),
                  node("UVIndex", {ints(index)})}));
      layer.add(element("LayerElementUV"));
    }
    g.add(node("LayerElementMaterial", {i32(0)},
               {node("Version", {i32(101)}), node("Name", {text("")}), node("MappingInformationType", {text("AllSame")}),
                node("ReferenceInformationType", {text("IndexToDirect")}), node("Materials", {ints({0})})}));
    layer.add(element("LayerElementMaterial"));
    g.add(std::move(layer));
    return g;
  }

  // The provenance as user properties of the mesh object (Blender shows them as custom
  // properties; the FBX SDK as user-defined properties).
  FbxNode mesh_model_node(std::int64_t id) const {
    auto user = [](const std::string& name, const std::string& value) { return p(name, "KString", "", "U", {text(value)}); };
    FbxNode props = node("Properties70", {},
                         {user("caliper_body_model", provenance_.body_model), user("caliper_model_source", provenance_.model_source),
                          user("caliper_licence", provenance_.licence),
                          user("caliper_commercial_use", provenance_.commercial_use ? "allowed" : "non-commercial use only"),
                          user("caliper_sex", provenance_.sex), user("caliper_regressor", provenance_.regressor),
                          user("caliper_measurements", measurements_text(provenance_)),
                          user("caliper_version", provenance_.caliper_version),
                          user("caliper_skeleton", to_string(options_.skeleton)),
                          user("copyright", provenance_notice(provenance_))});
    return node("Model", {i64(id), text(object_name(options_.mesh_name, "Model")), text("Mesh")},
                {node("Version", {i32(232)}), std::move(props), node("Shading", {{'C', std::string(1, 'T')}}),
                 node("Culling", {text("CullingOff")})});
  }

  static FbxNode material_node(std::int64_t id) {
    // The glTF export's skin tone, in sRGB (FBX colours are not linear).
    return node("Material", {i64(id), text(object_name("skin", "Material")), text("")},
                {node("Version", {i32(102)}), node("ShadingModel", {text("lambert")}), node("MultiLayer", {i32(0)}),
                 node("Properties70", {}, {p("DiffuseColor", "Color", "", "A", {f64(0.878), f64(0.675), f64(0.569)})})});
  }

  static FbxNode limb_node(const ExportRig& rig, int j, std::int64_t id) {
    const Eigen::Vector3d t = kFileUnitsPerMetre * rig.local_translation(j);
    // FBX's default rotation order XYZ: R = Rz·Ry·Rx, in degrees.
    const Eigen::Vector3d zyx = rig.local_rotation(j).eulerAngles(2, 1, 0) * (180.0 / M_PI);
    return node("Model", {i64(id), text(object_name(rig.names[static_cast<size_t>(j)], "Model")), text("LimbNode")},
                {node("Version", {i32(232)}),
                 node("Properties70", {},
                      {p("Lcl Translation", "Lcl Translation", "", "A", {f64(t.x()), f64(t.y()), f64(t.z())}),
                       p("Lcl Rotation", "Lcl Rotation", "", "A", {f64(zyx(2)), f64(zyx(1)), f64(zyx(0))}),
                       p("Lcl Scaling", "Lcl Scaling", "", "A", {f64(1), f64(1), f64(1)}),
                       p("InheritType", "enum", "", "", {i32(1)})})});
  }

  // Shape direction k at weight 1 (β_k + 1 SD), as the control points it moves and how far, with
  // the change of their normals. A point neither moves nor turns is left out (FBX shapes are sparse).
  void add_blend_shapes(std::int64_t geometry) {
    const Faces& faces = model_.faces();
    const Vertices normals = vertex_normals(rest_, faces);
    const std::int64_t blend_shape = new_id();
    objects_.add(node("Deformer", {i64(blend_shape), text(object_name("shapes", "Deformer")), text("BlendShape")},
                      {node("Version", {i32(100)})}));
    connect(blend_shape, geometry);
    for (int k = 0; k < model_.shape_count(); ++k) {
      const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>> direction(
          model_.data().shape_directions.col(k).data(), rest_.rows(), 3);
      const Vertices turned = vertex_normals(rest_ + direction, faces) - normals;
      std::vector<std::int32_t> indexes;
      std::vector<double> moved, turn;
      for (Eigen::Index v = 0; v < rest_.rows(); ++v) {
        if (direction.row(v).isZero(0) && turned.row(v).isZero(0)) continue;
        indexes.push_back(static_cast<std::int32_t>(v));
        // Single precision is what engines keep (and what the body model evaluates S·β in);
        // doubles rounded to it compress to about half.
        for (int c = 0; c < 3; ++c) moved.push_back(static_cast<float>(kFileUnitsPerMetre * direction(v, c)));
        for (int c = 0; c < 3; ++c) turn.push_back(static_cast<float>(turned(v, c)));
      }
      const std::string name = "shape_" + std::to_string(k);
      const std::int64_t channel = new_id(), shape = new_id();
      objects_.add(node("Geometry", {i64(shape), text(object_name(name, "Geometry")), text("Shape")},
                        {node("Version", {i32(100)}), node("Indexes", {ints(indexes)}), node("Vertices", {doubles(moved)}),
                         node("Normals", {doubles(turn)})}));
      objects_.add(node("Deformer", {i64(channel), text(object_name(name, "SubDeformer")), text("BlendShapeChannel")},
                        {node("Version", {i32(100)}), node("DeformPercent", {f64(0.0)}), node("FullWeights", {doubles({100.0})}),
                         node("Properties70", {}, {p("DeformPercent", "Number", "", "A", {f64(0.0)})})}));
      connect(channel, blend_shape);
      connect(shape, channel);
    }
    counts_["Geometry"] += model_.shape_count();
    counts_["Deformer"] += 1 + model_.shape_count();
  }

  void add_clusters(const ExportRig& rig, const std::vector<std::int64_t>& bone, std::int64_t skin) {
    std::vector<std::vector<std::int32_t>> indexes(static_cast<size_t>(rig.size()));
    std::vector<std::vector<double>> weights(static_cast<size_t>(rig.size()));
    for (Eigen::Index v = 0; v < rest_.rows(); ++v) {
      const export_detail::Influences inf = export_detail::top_influences(model_.data().skin_weights, v);
      for (int k = 0; k < 4; ++k)
        if (inf.weights[static_cast<size_t>(k)] > 0) {
          indexes[static_cast<size_t>(inf.joints[static_cast<size_t>(k)])].push_back(static_cast<std::int32_t>(v));
          weights[static_cast<size_t>(inf.joints[static_cast<size_t>(k)])].push_back(inf.weights[static_cast<size_t>(k)]);
        }
    }
    for (int j = 0; j < rig.size(); ++j) {
      const std::int64_t cluster = new_id();
      const Eigen::Matrix4d link = rest_world(rig, j);
      FbxNode c = node("Deformer", {i64(cluster), text(object_name(rig.names[static_cast<size_t>(j)], "SubDeformer")), text("Cluster")},
                       {node("Version", {i32(100)}), node("UserData", {text(""), text("")})});
      if (!indexes[static_cast<size_t>(j)].empty()) {
        c.add(node("Indexes", {ints(indexes[static_cast<size_t>(j)])}));
        c.add(node("Weights", {doubles(weights[static_cast<size_t>(j)])}));
      }
      c.add(node("Transform", {doubles(column_major(link.inverse()))}));
      c.add(node("TransformLink", {doubles(column_major(link))}));
      objects_.add(std::move(c));
      connect(cluster, skin);
      connect(bone[static_cast<size_t>(j)], cluster);
    }
  }

  void add_bind_pose(const ExportRig& rig, const std::vector<std::int64_t>& bone, std::int64_t mesh_model) {
    FbxNode pose = node("Pose", {i64(new_id()), text(object_name("BindPose", "Pose")), text("BindPose")},
                        {node("Type", {text("BindPose")}), node("Version", {i32(100)}), node("NbPoseNodes", {i32(rig.size() + 1)})});
    pose.add(node("PoseNode", {}, {node("Node", {i64(mesh_model)}), node("Matrix", {doubles(column_major(Eigen::Matrix4d::Identity()))})}));
    for (int j = 0; j < rig.size(); ++j)
      pose.add(node("PoseNode", {}, {node("Node", {i64(bone[static_cast<size_t>(j)])}), node("Matrix", {doubles(column_major(rest_world(rig, j)))})}));
    objects_.add(std::move(pose));
  }

  const BodyModel& model_;
  const Vertices& rest_;
  const ExportOptions& options_;
  const Provenance provenance_;
  std::int64_t next_id_ = 1000000;
  FbxNode objects_ = node("Objects");
  FbxNode connections_ = node("Connections");
  std::map<std::string, int> counts_;
};

}  // namespace

std::string write_fbx(const BodyModel& model, const Vertices& rest, const ExportOptions& options) {
  check_fbx_inputs(model, rest);
  return SceneBuilder(model, rest, options).bytes();
}

void save_fbx(const std::string& path, const BodyModel& model, const Vertices& rest, const ExportOptions& options) {
  export_detail::write_file(path, write_fbx(model, rest, options));
}

}  // namespace caliper
