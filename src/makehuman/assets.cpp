// Readers for MakeHuman's CC0 assets (MPFB2 layout). Written from the format facts in the
// assets' README and the files themselves; no MakeHuman/MPFB2 code was read.
#include "caliper/makehuman/assets.h"

#include <zlib.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>

#include "caliper/errors.h"
#include "gate.h"
#include "json_read.h"

namespace caliper::makehuman {

namespace fs = std::filesystem;

namespace {

constexpr double kDecimetre = 0.1;  // hm08 units → metres
constexpr double kMaxDisplacementUnits = 100;  // a target's largest accepted move, decimetres (10 m)

std::string read_text(const fs::path& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw Error(ErrorKind::Io, "cannot open '" + path.string() + "'", path.string());
  std::ostringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

nlohmann::json read_json(const fs::path& path) {
  const std::string text = read_text(path);
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw Error(ErrorKind::Format, path.string() + ": not valid JSON (" + e.what() + ")", path.string());
  }
}

std::string gunzip(const std::string& path) {
  gzFile f = gzopen(path.c_str(), "rb");
  if (!f) throw Error(ErrorKind::Io, "cannot open '" + path + "'", path);
  std::string out;
  char buf[1 << 16];
  int n = 0;
  while ((n = gzread(f, buf, sizeof buf)) > 0) out.append(buf, static_cast<size_t>(n));
  int code = Z_OK;
  const char* message = gzerror(f, &code);
  const std::string what = message ? message : "";
  const bool plain = gzdirect(f) == 1;
  gzclose(f);
  if (n < 0 || (code != Z_OK && code != Z_STREAM_END))
    throw Error(ErrorKind::Format, path + ": damaged gzip stream (" + what + ")", path);
  if (plain && !out.empty()) throw Error(ErrorKind::Format, path + ": not a gzip file", path);
  return out;
}

// Whitespace-separated fields of one line, as views into `line`.
std::vector<std::string_view> fields(std::string_view line) {
  std::vector<std::string_view> out;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    size_t j = i;
    while (j < line.size() && line[j] != ' ' && line[j] != '\t' && line[j] != '\r') ++j;
    if (j > i) out.push_back(line.substr(i, j - i));
    i = j;
  }
  return out;
}

bool parse_number(std::string_view s, double& v) {
  // from_chars rejects a leading '+'; targets never write one but be lenient.
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  return ec == std::errc() && p == s.data() + s.size() && std::isfinite(v);
}

bool parse_int(std::string_view s, long& v) {
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  return ec == std::errc() && p == s.data() + s.size();
}

std::string stem_of_target(const fs::path& p) {
  std::string name = p.filename().string();
  const std::string suffix = ".target.gz";
  if (name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0)
    name.resize(name.size() - suffix.size());
  return name;
}

void require_dir(const fs::path& p, const std::string& what) {
  std::error_code ec;
  if (!fs::is_directory(p, ec))
    throw Error(ErrorKind::Io,
                "'" + p.string() + "' is not a folder: expected " + what +
                    " (a MakeHuman assets folder in MPFB2 layout has 3dobjs/, mesh_metadata/, targets/, rigs/)",
                "--assets");
}

// Calls visit(line_number, fields) for every line of `text` that has fields (1-based numbers,
// so errors can point at the line).
template <class Visit>
void for_each_line(const std::string& text, Visit&& visit) {
  size_t start = 0;
  int line_no = 0;
  while (start < text.size()) {
    size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    const std::string_view line(text.data() + start, end - start);
    start = end + 1;
    ++line_no;
    const auto f = fields(line);
    if (!f.empty()) visit(line_no, f);
  }
}

}  // namespace

namespace {
// The reader itself; the public function below is its gate.
Target read_target_lines(const std::string& path, int vertex_count) {
  Target t;
  t.path = path;
  t.name = stem_of_target(path);
  const std::string text = gunzip(path);
  for_each_line(text, [&](int line_no, const auto& f) {
    if (f[0].front() == '#') return;
    auto bad = [&](const std::string& what) {
      throw Error(ErrorKind::Format, path + ": line " + std::to_string(line_no) + ": " + what, t.name);
    };
    if (f.size() != 4) bad("expected 'index dx dy dz', got " + std::to_string(f.size()) + " fields");
    long index = 0;
    if (!parse_int(f[0], index)) bad("vertex index '" + std::string(f[0]) + "' is not an integer");
    if (index < 0 || index >= vertex_count)
      bad("vertex index " + std::to_string(index) + " outside [0, " + std::to_string(vertex_count) + ")");
    Eigen::Vector3f d;
    for (int c = 0; c < 3; ++c) {
      double v = 0;
      if (!parse_number(f[static_cast<size_t>(c) + 1], v)) bad("'" + std::string(f[static_cast<size_t>(c) + 1]) + "' is not a finite number");
      // The target is kept in floats: a number beyond float's range would become infinite. No
      // real displacement comes near the bound (MakeHuman's body is about 17 units tall).
      if (std::abs(v) > kMaxDisplacementUnits)
        bad("displacement '" + std::string(f[static_cast<size_t>(c) + 1]) + "' is outside [-" +
            std::to_string(static_cast<int>(kMaxDisplacementUnits)) + ", " +
            std::to_string(static_cast<int>(kMaxDisplacementUnits)) + "] (decimetres)");
      d(c) = static_cast<float>(v * kDecimetre);
    }
    t.indices.push_back(static_cast<int>(index));
    t.deltas.push_back(d);
  });
  return t;
}
}  // namespace

Target read_target(const std::string& path, int vertex_count) {
  return gate("MakeHuman target '" + path + "'", "target", [&] { return read_target_lines(path, vertex_count); });
}

namespace {
// The reader itself; the public function below is its gate.
BaseMesh read_base_mesh_files(const std::string& dir) {
  const fs::path root(dir);
  require_dir(root, "an assets folder");
  const fs::path obj = root / "3dobjs" / "base.obj";
  const std::string text = read_text(obj);
  BaseMesh m;
  std::vector<double> xyz;
  std::vector<std::array<int, 3>> tris;
  std::vector<std::vector<long>> polygons, polygon_uvs;  // vertex and `vt` indices, 0-based (−1: none)
  std::vector<std::array<double, 2>> uvs;
  for_each_line(text, [&](int line_no, const auto& f) {
    auto bad = [&](const std::string& what) {
      throw Error(ErrorKind::Format, obj.string() + ": line " + std::to_string(line_no) + ": " + what, "base.obj");
    };
    if (f[0] == "v") {
      if (f.size() < 4) bad("a vertex needs 3 coordinates");
      for (int c = 1; c <= 3; ++c) {
        double v = 0;
        if (!parse_number(f[static_cast<size_t>(c)], v)) bad("'" + std::string(f[static_cast<size_t>(c)]) + "' is not a finite number");
        xyz.push_back(v * kDecimetre);
      }
    } else if (f[0] == "vt") {
      std::array<double, 2> uv{-1, -1};  // malformed: never valid, so the body gets no UVs
      if (f.size() >= 3) {
        double a = 0, b = 0;
        if (parse_number(f[1], a) && parse_number(f[2], b)) uv = {a, b};
      }
      uvs.push_back(uv);
    } else if (f[0] == "f") {
      if (f.size() < 4) bad("a face needs at least 3 vertices");
      std::vector<long> poly, poly_uv;
      for (size_t k = 1; k < f.size(); ++k) {
        const size_t slash = f[k].find('/');
        const std::string_view idx = f[k].substr(0, slash);
        long v = 0;
        if (!parse_int(idx, v) || v < 1) bad("face vertex '" + std::string(f[k]) + "' is not a positive index");
        poly.push_back(v - 1);
        long t = 0;
        const std::string_view tail = slash == std::string_view::npos ? std::string_view{} : f[k].substr(slash + 1);
        poly_uv.push_back(parse_int(tail.substr(0, tail.find('/')), t) && t >= 1 ? t - 1 : -1);
      }
      polygons.push_back(std::move(poly));
      polygon_uvs.push_back(std::move(poly_uv));
    }
  });
  const long n = static_cast<long>(xyz.size() / 3);
  if (n < kBodyVertexCount)
    throw Error(ErrorKind::Format, obj.string() + ": has " + std::to_string(n) + " vertices, hm08 has at least " +
                                       std::to_string(kBodyVertexCount), "base.obj");
  m.vertices = Eigen::Map<const Vertices>(xyz.data(), n, 3);
  // Body faces are those using body vertices only; quads are split along their first diagonal,
  // and their texture coordinates with them.
  std::vector<std::array<long, 3>> uv_tris;
  for (size_t p = 0; p < polygons.size(); ++p) {
    const auto& poly = polygons[p];
    const auto& puv = polygon_uvs[p];
    for (long v : poly)
      if (v >= n) throw Error(ErrorKind::Format, obj.string() + ": face vertex " + std::to_string(v + 1) + " beyond the vertex list", "base.obj");
    if (*std::max_element(poly.begin(), poly.end()) >= kBodyVertexCount) continue;
    for (size_t k = 1; k + 1 < poly.size(); ++k) {
      tris.push_back({static_cast<int>(poly[0]), static_cast<int>(poly[k]), static_cast<int>(poly[k + 1])});
      uv_tris.push_back({puv[0], puv[k], puv[k + 1]});
    }
  }
  m.body_faces.resize(static_cast<Eigen::Index>(tris.size()), 3);
  for (size_t i = 0; i < tris.size(); ++i)
    m.body_faces.row(static_cast<Eigen::Index>(i)) << tris[i][0], tris[i][1], tris[i][2];
  const MeshCheck check = check_mesh(m.body_faces, kBodyVertexCount);
  if (!check.closed || !check.manifold || !check.consistently_oriented || check.unused_vertices)
    throw Error(ErrorKind::Format,
                obj.string() + ": the body (vertices 0–" + std::to_string(kBodyVertexCount - 1) +
                    ") is not a closed, manifold, consistently oriented surface (" + std::to_string(check.boundary_edges) +
                    " boundary edges, " + std::to_string(check.nonmanifold_edges) + " non-manifold edges, " +
                    std::to_string(check.unused_vertices) + " unused vertices)",
                "base.obj");
  // Outward orientation: the enclosed volume must come out positive.
  double volume = 0;
  const Vertices body = m.vertices.topRows(kBodyVertexCount);
  for (Eigen::Index f = 0; f < m.body_faces.rows(); ++f)
    volume += body.row(m.body_faces(f, 0)).dot(body.row(m.body_faces(f, 1)).cross(body.row(m.body_faces(f, 2)))) / 6;
  if (volume < 0) m.body_faces.col(1).swap(m.body_faces.col(2));

  // Texture coordinates, all or none: every body corner needs a `vt` in [0, 1].
  bool textured = !uv_tris.empty();
  std::vector<long> used;
  for (const auto& t : uv_tris)
    for (long i : t) {
      const bool valid = i >= 0 && i < static_cast<long>(uvs.size()) && uvs[static_cast<size_t>(i)][0] >= 0 &&
                         uvs[static_cast<size_t>(i)][0] <= 1 && uvs[static_cast<size_t>(i)][1] >= 0 &&
                         uvs[static_cast<size_t>(i)][1] <= 1;
      textured = textured && valid;
      if (valid) used.push_back(i);
    }
  if (textured) {
    std::sort(used.begin(), used.end());
    used.erase(std::unique(used.begin(), used.end()), used.end());
    std::map<long, int> compact;
    m.body_uv.resize(static_cast<Eigen::Index>(used.size()), 2);
    for (size_t k = 0; k < used.size(); ++k) {
      compact[used[k]] = static_cast<int>(k);
      m.body_uv.row(static_cast<Eigen::Index>(k)) << uvs[static_cast<size_t>(used[k])][0], uvs[static_cast<size_t>(used[k])][1];
    }
    m.body_uv_faces.resize(static_cast<Eigen::Index>(uv_tris.size()), 3);
    for (size_t i = 0; i < uv_tris.size(); ++i)
      for (int c = 0; c < 3; ++c)
        m.body_uv_faces(static_cast<Eigen::Index>(i), c) = compact.at(uv_tris[i][static_cast<size_t>(c)]);
    if (volume < 0) m.body_uv_faces.col(1).swap(m.body_uv_faces.col(2));  // same corner order as the faces
  }

  const fs::path groups_path = root / "mesh_metadata" / "basemesh_vertex_groups.json";
  const nlohmann::json groups = read_json(groups_path);
  if (!groups.is_object()) throw Error(ErrorKind::Format, groups_path.string() + ": expected an object", "vertex_groups");
  for (const auto& [name, ranges] : groups.items()) {
    std::vector<int>& out = m.groups[name];
    if (!ranges.is_array()) throw Error(ErrorKind::Format, groups_path.string() + ": group '" + name + "' is not a list", name);
    for (const auto& r : ranges) {
      if (!r.is_array() || r.size() != 2 || !r[0].is_number_integer() || !r[1].is_number_integer())
        throw Error(ErrorKind::Format, groups_path.string() + ": group '" + name + "' has a range that is not [first, last]", name);
      const long a = r[0].get<long>(), b = r[1].get<long>();
      if (a < 0 || b < a || b >= n)
        throw Error(ErrorKind::Format, groups_path.string() + ": group '" + name + "' range out of [0, " + std::to_string(n) + ")", name);
      for (long v = a; v <= b; ++v) out.push_back(static_cast<int>(v));
    }
  }

  const fs::path mirror_path = root / "mesh_metadata" / "hm08.mirror";
  const std::string mirror_text = read_text(mirror_path);
  m.mirror.assign(static_cast<size_t>(n), -1);
  for_each_line(mirror_text, [&](int line_no, const auto& f) {
    long a = 0, b = 0;
    if (f.size() < 2 || !parse_int(f[0], a) || !parse_int(f[1], b) || a < 0 || b < 0 || a >= n || b >= n)
      throw Error(ErrorKind::Format, mirror_path.string() + ": line " + std::to_string(line_no) + ": expected 'index mirror side'",
                  "hm08.mirror");
    m.mirror[static_cast<size_t>(a)] = static_cast<int>(b);
  });
  for (long v = 0; v < kBodyVertexCount; ++v)
    if (m.mirror[static_cast<size_t>(v)] < 0)
      throw Error(ErrorKind::Format, mirror_path.string() + ": body vertex " + std::to_string(v) + " has no mirror", "hm08.mirror");
  return m;
}
}  // namespace

BaseMesh read_base_mesh(const std::string& dir) {
  return gate("MakeHuman base mesh in '" + dir + "'", "base_mesh", [&] { return read_base_mesh_files(dir); });
}

int Rig::bone_index(const std::string& name) const {
  for (size_t i = 0; i < bones.size(); ++i)
    if (bones[i].name == name) return static_cast<int>(i);
  return -1;
}

namespace {

using detail::JsonPlace;

// A bone's head or tail (`end`): the vertices whose mean is the joint.
std::vector<int> read_joint(const nlohmann::json& def, const JsonPlace& bone, const std::string& end, const BaseMesh& mesh) {
  const int n = static_cast<int>(mesh.vertices.rows());
  const JsonPlace at = bone / end;
  const nlohmann::json& j = detail::json_require(def, end, bone);
  const std::string strategy = detail::json_string(detail::json_require(j, "strategy", at), at / "strategy");
  std::vector<int> out;
  if (strategy == "CUBE") {
    const std::string cube = detail::json_string(detail::json_require(j, "cube_name", at), at / "cube_name");
    auto it = mesh.groups.find(cube);
    if (it == mesh.groups.end() || it->second.empty()) (at / "cube_name").fail("names an unknown joint cube '" + cube + "'");
    out = it->second;
  } else if (strategy == "VERTEX") {
    out.push_back(static_cast<int>(detail::json_integer(detail::json_require(j, "vertex_index", at), at / "vertex_index", 0, n - 1)));
  } else if (strategy == "MEAN") {
    const nlohmann::json& list = detail::json_require(j, "vertex_indices", at);
    if (!list.is_array() || list.empty()) (at / "vertex_indices").fail("must be a non-empty list of vertex indices");
    for (const auto& v : list) out.push_back(static_cast<int>(detail::json_integer(v, at / "vertex_indices", 0, n - 1)));
  } else {
    (at / "strategy").fail("is '" + strategy + "', expected CUBE, VERTEX or MEAN");
  }
  return out;
}

// The bones of rig.<name>.json into r.bones, parents before children (the file is alphabetical).
void read_bones(const fs::path& path, const BaseMesh& mesh, Rig& r) {
  const nlohmann::json rig = read_json(path);
  if (!rig.is_object() || rig.empty()) throw Error(ErrorKind::Format, path.string() + ": no bones", "rig");
  std::vector<std::string> pending;
  for (const auto& [bone, def] : rig.items()) pending.push_back(bone);
  while (!pending.empty()) {
    bool progressed = false;
    for (auto it = pending.begin(); it != pending.end();) {
      const JsonPlace bone{path.string(), *it};
      const nlohmann::json& def = rig.at(*it);
      const std::string parent = detail::json_string_or(def, "parent", "", bone);
      if (parent.empty() || r.bone_index(parent) >= 0) {
        r.bones.push_back({*it, parent, read_joint(def, bone, "head", mesh), read_joint(def, bone, "tail", mesh)});
        it = pending.erase(it);
        progressed = true;
      } else {
        ++it;
      }
    }
    if (!progressed) throw Error(ErrorKind::Format, path.string() + ": bone '" + pending.front() + "' has a missing or cyclic parent", pending.front());
  }
}

// weights.<name>.json into r.weights, normalised to sum 1 per vertex; every body vertex needs some.
void read_bone_weights(const fs::path& path, int n, Rig& r) {
  const nlohmann::json weights = read_json(path);
  const JsonPlace doc{path.string(), ""};
  const nlohmann::json& bone_weights = detail::json_require(weights, "weights", doc);
  if (!bone_weights.is_object()) (doc / "weights").fail("must be an object of bone: [[vertex, weight], ...]");
  r.weights.assign(static_cast<size_t>(n), {});
  for (const auto& [bone, list] : bone_weights.items()) {
    const JsonPlace at = doc / "weights" / bone;
    const int b = r.bone_index(bone);
    if (b < 0) throw Error(ErrorKind::Format, path.string() + ": weights for unknown bone '" + bone + "'", bone);
    if (!list.is_array()) at.fail("must be a list of [vertex, weight]");
    for (const auto& e : list) {
      if (!e.is_array() || e.size() != 2) at.fail("has an entry that is not [vertex, weight]");
      const int v = static_cast<int>(detail::json_integer(e[0], at, 0, n - 1));
      const double w = detail::json_number(e[1], at);
      // A fraction of the vertex (cmu_mb's are in [0.0001, 1]); 1e308 would overflow the float.
      if (!(w >= 0 && w <= 1)) at.fail("has weight " + e[1].dump() + " for vertex " + std::to_string(v) + ", expected [0, 1]");
      if (w > 0) r.weights[static_cast<size_t>(v)].push_back({b, static_cast<float>(w)});
    }
  }
  for (int v = 0; v < n; ++v) {
    auto& ws = r.weights[static_cast<size_t>(v)];
    double s = 0;
    for (const auto& [b, w] : ws) s += w;
    if (s <= 0) {
      if (v < kBodyVertexCount)
        throw Error(ErrorKind::Format, path.string() + ": body vertex " + std::to_string(v) + " has no weights", "weights");
      continue;
    }
    for (auto& bw : ws) bw.second = static_cast<float>(bw.second / s);
  }
}

}  // namespace

namespace {
// The reader itself; the public function below is its gate.
Rig read_rig_files(const std::string& dir, const BaseMesh& mesh, const std::string& name) {
  const fs::path folder = fs::path(dir) / "rigs" / "standard";
  Rig r;
  read_bones(folder / ("rig." + name + ".json"), mesh, r);
  read_bone_weights(folder / ("weights." + name + ".json"), static_cast<int>(mesh.vertices.rows()), r);
  return r;
}
}  // namespace

Rig read_rig(const std::string& dir, const BaseMesh& mesh, const std::string& name) {
  return gate("MakeHuman rig '" + name + "'", "rig", [&] { return read_rig_files(dir, mesh, name); });
}

namespace {
// The assets folder inside what a user downloads, taken as it comes: the data folder itself, a
// clone of the MPFB2 repository (its data is src/mpfb/data), or an unpacked archive that wraps
// either in one folder (mpfb2-master/). The first with 3dobjs/base.obj; `dir` itself otherwise,
// so the checks below say what is missing there.
fs::path find_assets_root(const fs::path& dir) {
  std::error_code ec;
  std::vector<fs::path> bases = {dir};
  std::vector<fs::path> subfolders;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    if (it->is_directory(ec)) subfolders.push_back(it->path());
  if (subfolders.size() == 1) bases.push_back(subfolders.front());
  for (const fs::path& base : bases)
    for (const fs::path& candidate : {base, base / "src" / "mpfb" / "data", base / "mpfb" / "data", base / "data"})
      if (fs::is_regular_file(candidate / "3dobjs" / "base.obj", ec)) return candidate;
  return dir;
}

// The reader itself; the public function below is its gate.
Assets load_assets_folder(const std::string& given, const LoadOptions& options) {
  const fs::path root = find_assets_root(given);
  const std::string dir = root.string();
  require_dir(root, "a MakeHuman assets folder");
  for (const char* sub : {"3dobjs", "mesh_metadata", "targets/macrodetails", "rigs/standard"})
    require_dir(root / sub, std::string("its ") + sub + " folder");
  Assets a;
  a.dir = dir;
  a.mesh = read_base_mesh(dir);
  a.rig = read_rig(dir, a.mesh);
  const int n = static_cast<int>(a.mesh.vertices.rows());

  // Macro targets by family: a family's members share a folder and a name pattern.
  struct Family {
    fs::path folder;
    std::function<bool(const std::string&)> member;
  };
  auto starts = [](const std::string& s, const std::string& p) { return s.compare(0, p.size(), p) == 0; };
  const fs::path macro = root / "targets" / "macrodetails";
  const std::vector<Family> families = {
      {macro, [&](const std::string& s) { return !starts(s, "universal-"); }},  // race-gender-age
      {macro, [&](const std::string& s) { return starts(s, "universal-"); }},   // gender-age-muscle-weight
      {macro / "height", [](const std::string&) { return true; }},
      {macro / "proportions", [](const std::string&) { return true; }},
      {root / "targets" / "breast", [&](const std::string& s) { return starts(s, "female-") || starts(s, "male-"); }},
  };
  for (const auto& fam : families) {
    std::error_code ec;
    if (!fs::is_directory(fam.folder, ec)) throw Error(ErrorKind::Io, "missing folder '" + fam.folder.string() + "'", "--assets");
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(fam.folder, ec))
      if (e.is_regular_file() && e.path().filename().string().size() > 10 &&
          e.path().filename().string().find(".target.gz") != std::string::npos && fam.member(stem_of_target(e.path())))
        files.push_back(e.path());
    std::sort(files.begin(), files.end());
    if (files.empty()) throw Error(ErrorKind::Io, "no targets in '" + fam.folder.string() + "'", "--assets");
    std::vector<Target> members;
    for (const auto& f : files) {
      const std::string stem = stem_of_target(f);
      if (options.skip_baby && stem.find("-baby") != std::string::npos) continue;
      members.push_back(read_target(f.string(), n));
    }
    // A family whose typical member moves (nearly) every vertex is dense: a member that moves
    // fewer than half as many as the median was cut short (README: one such file in the source).
    std::vector<size_t> counts;
    for (const auto& t : members)
      if (!t.indices.empty()) counts.push_back(t.indices.size());
    std::sort(counts.begin(), counts.end());
    const size_t median = counts.empty() ? 0 : counts[counts.size() / 2];
    const bool dense = median > static_cast<size_t>(0.9 * n);
    for (auto& t : members) {
      if (dense && !t.indices.empty() && t.indices.size() < median / 2) {
        a.problems.push_back({t.name, "truncated: " + std::to_string(t.indices.size()) + " entries where its siblings have about " +
                                          std::to_string(median) + "; skipped"});
        continue;
      }
      a.macro_targets.push_back(std::move(t));
    }
  }
  for (const char* part : {"arms", "feet", "hands", "legs", "neck", "torso"}) {
    const fs::path folder = root / "targets" / part;
    std::error_code ec;
    if (!fs::is_directory(folder, ec)) throw Error(ErrorKind::Io, "missing folder '" + folder.string() + "'", "--assets");
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(folder, ec)) {
      const std::string s = e.path().filename().string();
      if (starts(s, "measure-") && s.find(".target.gz") != std::string::npos) files.push_back(e.path());
    }
    std::sort(files.begin(), files.end());
    for (const auto& f : files) a.modifier_targets.push_back(read_target(f.string(), n));
  }
  if (a.modifier_targets.empty()) throw Error(ErrorKind::Io, "no measure-* targets under '" + (root / "targets").string() + "'", "--assets");
  return a;
}
}  // namespace

Assets load_assets(const std::string& dir, const LoadOptions& options) {
  return gate("MakeHuman assets in '" + dir + "'", "assets", [&] { return load_assets_folder(dir, options); });
}

}  // namespace caliper::makehuman
