// Writes the fuzzers' derived seeds into OUT/<gate>/ (scripts/fuzz.sh and the replay tests run
// it): files built from the unit tests' toy body (tests/unit/fixtures.h), the small arrays of the
// built-in model and examples/, plus the audit's reproducers (docs/reliability.md) in each gate's
// form.
// Derived, so never committed. Usage: fuzz_make_seeds OUT
#include <zip.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>

#include "caliper/io/model_files.h"
#include "caliper/io/npz.h"
#include "fixtures.h"
#include "fuzz_support.h"

using namespace caliper;
namespace fs = std::filesystem;

namespace {

using Entries = std::map<std::string, std::string>;

// The .npy bytes of every entry of an .npz (names without ".npy"), or only those up to max_bytes.
Entries read_entries(const std::string& path, zip_uint64_t max_bytes = ~zip_uint64_t{0}) {
  int err = 0;
  std::unique_ptr<zip_t, int (*)(zip_t*)> z(zip_open(path.c_str(), ZIP_RDONLY, &err), zip_close);
  if (!z) throw std::runtime_error("cannot open " + path);
  Entries out;
  for (zip_int64_t i = 0; i < zip_get_num_entries(z.get(), 0); ++i) {
    zip_stat_t st;
    if (zip_stat_index(z.get(), static_cast<zip_uint64_t>(i), 0, &st) != 0 || st.size > max_bytes) continue;
    std::string bytes(st.size, '\0');
    std::unique_ptr<zip_file_t, int (*)(zip_file_t*)> f(zip_fopen_index(z.get(), static_cast<zip_uint64_t>(i), 0), zip_fclose);
    if (!f || zip_fread(f.get(), bytes.data(), st.size) != static_cast<zip_int64_t>(st.size)) continue;
    std::string name = st.name;
    if (name.size() > 4 && name.ends_with(".npy")) name.resize(name.size() - 4);
    out[name] = bytes;
  }
  return out;
}

void write(const fs::path& path, const std::string& bytes) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << bytes;
}

std::string file_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

// The toy body in the layout SMPL's files use: dense template, N×3×K shapedirs, the joint
// regressor as a CSC sparse matrix, dense weights, kintree_table, f.
Entries smpl_entries(const BodyModelData& d) {
  // SMPL files have at least the 10 shape directions the loader keeps by default: zeros pad the toy's.
  const std::int64_t n = d.template_vertices.rows(), j = d.joint_regressor.rows();
  const std::int64_t k = std::max<std::int64_t>(d.shape_directions.cols(), 10);
  Entries e;
  std::vector<double> v, sd, w, data, indices, indptr = {0};
  for (std::int64_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) v.push_back(d.template_vertices(i, c));
  for (std::int64_t r = 0; r < 3 * n; ++r)
    for (std::int64_t s = 0; s < k; ++s) sd.push_back(s < d.shape_directions.cols() ? d.shape_directions(r, s) : 0.0);
  const Eigen::MatrixXd jr = Eigen::MatrixXd(d.joint_regressor), sw = Eigen::MatrixXd(d.skin_weights);
  for (std::int64_t col = 0; col < n; ++col) {
    for (std::int64_t row = 0; row < j; ++row)
      if (jr(row, col) != 0) { data.push_back(jr(row, col)); indices.push_back(static_cast<double>(row)); }
    indptr.push_back(static_cast<double>(data.size()));
  }
  for (std::int64_t i = 0; i < n; ++i)
    for (std::int64_t b = 0; b < j; ++b) w.push_back(sw(i, b));
  std::vector<std::int64_t> kintree;
  for (int p : d.parents) kintree.push_back(p);
  for (std::int64_t b = 0; b < j; ++b) kintree.push_back(b);
  Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor> f = d.faces;
  const std::vector<std::int64_t> faces(f.data(), f.data() + f.size());
  const auto to_i64 = [](const std::vector<double>& x) { return std::vector<std::int64_t>(x.begin(), x.end()); };
  e["v_template"] = npz::write_npy_f64(v, {n, 3});
  e["shapedirs"] = npz::write_npy_f64(sd, {n, 3, k});
  e["J_regressor_format"] = npz::write_npy_unicode("csc");
  e["J_regressor_data"] = npz::write_npy_f64(data, {static_cast<std::int64_t>(data.size())});
  e["J_regressor_indices"] = npz::write_npy_i64(to_i64(indices), {static_cast<std::int64_t>(indices.size())});
  e["J_regressor_indptr"] = npz::write_npy_i64(to_i64(indptr), {static_cast<std::int64_t>(indptr.size())});
  e["J_regressor_shape"] = npz::write_npy_i64({j, n}, {2});
  e["weights"] = npz::write_npy_f64(w, {n, j});
  e["kintree_table"] = npz::write_npy_i64(kintree, {2, j});
  e["f"] = npz::write_npy_i64(faces, {d.faces.rows(), 3});
  return e;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: fuzz_make_seeds OUT\n";
    return 2;
  }
  const fs::path out = argv[1];
  const fs::path tmp = out / "tmp";
  fs::create_directories(tmp);

  // Model files: the toy body as a native file and in SMPL's layout, and the audit's crafted
  // models — skin weights N×0, and an SMPL regressor declared (2^31 − 1, 8).
  const BodyModel toy = test::toy_model();
  save_model(toy, (tmp / "toy.npz").string());
  const Entries native = read_entries((tmp / "toy.npz").string());
  const Entries smpl = smpl_entries(toy.data());
  write(out / "model" / "toy-native", fuzz::join_entries(native));
  write(out / "model" / "toy-smpl", fuzz::join_entries(smpl));
  Entries no_columns = native;
  no_columns["skin_weights_shape"] = npz::write_npy_i64({toy.vertex_count(), 0}, {2});
  write(out / "model" / "skin-weights-no-columns", fuzz::join_entries(no_columns));
  Entries huge = smpl;
  huge["J_regressor_shape"] = npz::write_npy_i64({(std::int64_t{1} << 31) - 1, 8}, {2});
  write(out / "model" / "smpl-regressor-2e31-rows", fuzz::join_entries(huge));

  // Whole archives: the same two bodies zipped, and a zip bomb (40 MB of zeros in one entry,
  // about 40 KB deflated; beyond every read limit).
  write(out / "npz" / "toy-native.npz", file_bytes(tmp / "toy.npz"));
  npz::write_npz((tmp / "smpl.npz").string(), smpl);
  write(out / "npz" / "toy-smpl.npz", file_bytes(tmp / "smpl.npz"));
  std::string header = "{'descr': '|u1', 'fortran_order': False, 'shape': (40000000,), }";
  header.append(63 - (10 + header.size()) % 64, ' ');  // with the newline, a multiple of 64 as numpy pads
  std::string bomb = std::string("\x93NUMPY\x01\x00", 8) + static_cast<char>(header.size() + 1) + '\0' + header + '\n';
  bomb.append(40'000'000, '\0');
  npz::write_npz((tmp / "bomb.npz").string(), {{"weights", bomb}});
  write(out / "npz" / "zip-bomb.npz", file_bytes(tmp / "bomb.npz"));

  // Single arrays: every entry of the toy files and the built-in model's small arrays (names,
  // parents, landmarks, measurement definitions, metadata).
  for (const auto& [name, bytes] : native) write(out / "npy" / ("toy-" + name), bytes);
  for (const auto& [name, bytes] : smpl) write(out / "npy" / ("smpl-" + name), bytes);
  for (const auto& [name, bytes] : read_entries(models_dir() + "/mannequin-neutral.npz", 16384))
    write(out / "npy" / ("mannequin-" + name), bytes);

  // The project's example files (examples/README.md) for the two CSV gates.
  const fs::path examples = fs::path(CALIPER_SOURCE_DIR) / "examples";
  write(out / "ansur_csv" / "people.csv", file_bytes(examples / "people.csv"));
  write(out / "map_pairs" / "real-virtual-pairs.csv", file_bytes(examples / "real-virtual-pairs.csv"));

  fs::remove_all(tmp);
  return 0;
}
