#include "caliper/body/volume_polynomial.h"

#include <algorithm>
#include <array>
#include <queue>
#include <string>
#include <vector>

#include "caliper/errors.h"

namespace caliper {

namespace {

// Three-vectors as plain doubles for the per-face loops below (see add_lower_terms).
using Vec3 = std::array<double, 3>;
Vec3 row_of(const Vertices& v, Eigen::Index i) { return {v(i, 0), v(i, 1), v(i, 2)}; }
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Vec3 add(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// A face with corners a = μa + A·β, b = μb + B·β, c = μc + C·β (A, B, C: the corners' 3×K rows of
// S) adds det(a, b, c) = a·(b × c) to six times the volume. Expanded by degree in β:
//   1: det(μa, μb, μc)
//   β_k: A_k·(μb × μc) + B_k·(μc × μa) + C_k·(μa × μb)
//   β_k β_l: A_k·(B_l × μc + μb × C_l) + B_k·(C_l × μa)
//   β_k β_l β_m: A_k·(B_l × C_m)
// Only the parts symmetric in the β's indices act on β. The corners' rows of S are read from its
// transpose, where each vertex's 3×K block is contiguous (in S it is spread over K columns).

struct SixVolumeTerms {
  double c0 = 0;
  Eigen::VectorXd c1;  // K
  Eigen::MatrixXd c2;  // K×K, not yet symmetric
  Eigen::MatrixXd c3;  // K × K(K+1)/2: c3(k, {l, m}) = Σ over faces of the β_k β_l β_m and β_k β_m β_l terms
};

Eigen::MatrixXi pair_columns(Eigen::Index k) {  // column of the pair {l, m} (l ≤ m) in c3
  Eigen::MatrixXi pair(k, k);
  for (Eigen::Index l = 0, p = 0; l < k; ++l)
    for (Eigen::Index m = l; m < k; ++m, ++p) pair(l, m) = pair(m, l) = static_cast<int>(p);
  return pair;
}

// Degrees 0–2, face by face; for a block of faces the degree-2 vectors form two matrices and
// their sums are matrix products. The per-face loops read S by pointer, with the cross products
// written out: through Eigen's small-vector expressions they ran 40 times slower than the
// Release build in the sanitizer build (every expression a call there, -O1), and the estimator
// builds this polynomial once in every process (docs/reliability.md "CI time").
void add_lower_terms(const BodyModelData& d, const Eigen::MatrixXd& st, SixVolumeTerms& t) {
  const Vertices& mu = d.template_vertices;
  const Eigen::Index k = st.rows();
  constexpr Eigen::Index kBlock = 256;
  t.c1 = Eigen::VectorXd::Zero(k);
  t.c2 = Eigen::MatrixXd::Zero(k, k);
  Eigen::MatrixXd a_rows(3 * kBlock, k), b_rows(3 * kBlock, k), y(3 * kBlock, k), z(3 * kBlock, k);
  for (Eigen::Index f0 = 0; f0 < d.faces.rows(); f0 += kBlock) {
    const Eigen::Index nb = std::min(kBlock, d.faces.rows() - f0);
    for (Eigen::Index i = 0; i < nb; ++i) {
      const Eigen::Index ia = d.faces(f0 + i, 0), ib = d.faces(f0 + i, 1), ic = d.faces(f0 + i, 2);
      const Vec3 ma = row_of(mu, ia), mb = row_of(mu, ib), mc = row_of(mu, ic);
      const double* sa = st.data() + 3 * ia * k;  // the corner's K×3 block of Sᵀ: column j at j·K
      const double* sb = st.data() + 3 * ib * k;
      const double* sc = st.data() + 3 * ic * k;
      const Vec3 bc = cross(mb, mc), ca = cross(mc, ma), ab = cross(ma, mb);
      t.c0 += dot(ma, bc);
      for (Eigen::Index l = 0; l < k; ++l) {
        const Vec3 al = {sa[l], sa[k + l], sa[2 * k + l]}, bl = {sb[l], sb[k + l], sb[2 * k + l]},
                   cl = {sc[l], sc[k + l], sc[2 * k + l]};
        t.c1[l] += dot(al, bc) + dot(bl, ca) + dot(cl, ab);
        const Vec3 yl = add(cross(bl, mc), cross(mb, cl)), zl = cross(cl, ma);
        const Eigen::Index at = 3 * i + l * 3 * kBlock;  // (3i + j, l) in the column-major blocks
        for (int j = 0; j < 3; ++j) {
          a_rows.data()[at + j] = al[j];
          b_rows.data()[at + j] = bl[j];
          y.data()[at + j] = yl[j];
          z.data()[at + j] = zl[j];
        }
      }
    }
    const Eigen::Index rows = 3 * nb;
    t.c2.noalias() += a_rows.topRows(rows).transpose() * y.topRows(rows) + b_rows.topRows(rows).transpose() * z.topRows(rows);
  }
}

// For each face, the corner its cubic term is counted from (det is cyclic: any corner may come
// first). The fewer the owners, the cheaper the cubic (add_cubic_terms): greedy set cover, each
// owner the vertex with the most faces not yet owned (about half the vertices own them all).
std::vector<int> owner_corners(const Faces& faces, Eigen::Index vertex_count) {
  std::vector<std::vector<Eigen::Index>> faces_of(static_cast<size_t>(vertex_count));
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    for (int c = 0; c < 3; ++c) faces_of[static_cast<size_t>(faces(f, c))].push_back(f);
  std::vector<int> corner(static_cast<size_t>(faces.rows()), -1);
  auto unowned = [&](size_t v) {
    return std::count_if(faces_of[v].begin(), faces_of[v].end(), [&](Eigen::Index f) { return corner[static_cast<size_t>(f)] < 0; });
  };
  // (faces not yet owned, −vertex): a count may be stale (too high); it is re-counted when popped.
  std::priority_queue<std::pair<std::ptrdiff_t, Eigen::Index>> queue;
  for (size_t v = 0; v < faces_of.size(); ++v) queue.emplace(static_cast<std::ptrdiff_t>(faces_of[v].size()), -static_cast<Eigen::Index>(v));
  while (!queue.empty()) {
    const auto [count, minus_v] = queue.top();
    queue.pop();
    const auto v = static_cast<size_t>(-minus_v);
    const std::ptrdiff_t now = unowned(v);
    if (now == 0) continue;
    if (now < count) {
      queue.emplace(now, minus_v);
      continue;
    }
    for (const Eigen::Index f : faces_of[v])
      if (corner[static_cast<size_t>(f)] < 0)
        for (int c = 0; c < 3; ++c)
          if (static_cast<size_t>(faces(f, c)) == v) corner[static_cast<size_t>(f)] = c;
  }
  return corner;
}

// Degree 3. With each face rotated to start at its owner v, Σ_f A_k·(B_l × C_m) over v's faces is
// Σ_i S_vi,k · W_vi,lm, where (B β × C β)_i = βᵀ W_vi β sums B_jᵀC_k − B_kᵀC_j over v's faces ((i, j, k)
// cyclic). The K×K matrices W are summed per owner, and the products with the owners' rows of S
// are one matrix product per block of owners.
void add_cubic_terms(const BodyModelData& d, const Eigen::MatrixXd& st, SixVolumeTerms& t) {
  const Eigen::Index k = st.rows(), pairs = k * (k + 1) / 2;
  const std::vector<int> corner = owner_corners(d.faces, d.template_vertices.rows());
  std::vector<std::vector<Eigen::Index>> owned(static_cast<size_t>(d.template_vertices.rows()));
  for (Eigen::Index f = 0; f < d.faces.rows(); ++f) owned[static_cast<size_t>(d.faces(f, corner[static_cast<size_t>(f)]))].push_back(f);

  constexpr Eigen::Index kBlock = 128;  // owners per product
  t.c3 = Eigen::MatrixXd::Zero(k, pairs);
  Eigen::MatrixXd a_rows(3 * kBlock, k), w_pairs(pairs, 3 * kBlock);  // an owner's pairs contiguous
  std::array<Eigen::MatrixXd, 3> w;
  Eigen::Index in_block = 0;
  auto flush = [&] {
    t.c3.noalias() += a_rows.topRows(3 * in_block).transpose() * w_pairs.leftCols(3 * in_block).transpose();
    in_block = 0;
  };
  for (size_t v = 0; v < owned.size(); ++v) {
    if (owned[v].empty()) continue;
    for (auto& wi : w) wi.setZero(k, k);
    for (const Eigen::Index f : owned[v]) {
      const int first = corner[static_cast<size_t>(f)];
      const double* sb = st.data() + 3 * static_cast<Eigen::Index>(d.faces(f, (first + 1) % 3)) * k;
      const double* sc = st.data() + 3 * static_cast<Eigen::Index>(d.faces(f, (first + 2) % 3)) * k;
      for (int i = 0; i < 3; ++i) {  // W_i += B_j C_lᵀ − B_l C_jᵀ, column-major: (p, q) at p + K·q
        const double *bj = sb + ((i + 1) % 3) * k, *bl = sb + ((i + 2) % 3) * k;
        const double *cj = sc + ((i + 1) % 3) * k, *cl = sc + ((i + 2) % 3) * k;
        double* wi = w[static_cast<size_t>(i)].data();
        for (Eigen::Index q = 0; q < k; ++q)
          for (Eigen::Index p = 0; p < k; ++p) wi[p + k * q] += bj[p] * cl[q] - bl[p] * cj[q];
      }
    }
    for (int i = 0; i < 3; ++i) {
      const Eigen::Index row = 3 * in_block + i;
      const double* s_vi = st.data() + (3 * static_cast<Eigen::Index>(v) + i) * k;
      for (Eigen::Index l = 0; l < k; ++l) a_rows(row, l) = s_vi[l];
      const double* wi = w[static_cast<size_t>(i)].data();
      double* column = w_pairs.data() + row * pairs;
      for (Eigen::Index l = 0, p = 0; l < k; ++l)  // pairs in pair_columns()' order
        for (Eigen::Index m = l; m < k; ++m, ++p) column[p] = wi[l + k * m] + wi[m + k * l];
    }
    if (++in_block == kBlock) flush();
  }
  flush();
}

}  // namespace

VolumePolynomial::VolumePolynomial(const BodyModel& model) {
  SixVolumeTerms t;
  const Eigen::MatrixXd st = model.data().shape_directions.transpose();  // K×3N
  const Eigen::MatrixXi pair = pair_columns(st.rows());
  add_lower_terms(model.data(), st, t);
  add_cubic_terms(model.data(), st, t);
  // Six times the volume above. Symmetrised: the quadratic is (c2 + c2ᵀ)/2; the cubic term of
  // (k, l, m) is the mean of its six orders, (c3(k, {l, m}) + c3(l, {k, m}) + c3(m, {k, l}))/6.
  // The gradient is then c1 + 2·c2·β + 3·c3(β, β, ·).
  const Eigen::Index k = t.c1.size();
  constant_ = t.c0 / 6;
  linear_ = t.c1 / 6;
  quadratic_ = (t.c2 + t.c2.transpose()) / 12;
  cubic_.resize(k * k, k);
  for (Eigen::Index a = 0; a < k; ++a)
    for (Eigen::Index b = 0; b < k; ++b)
      for (Eigen::Index c = 0; c < k; ++c)
        cubic_(b + k * c, a) = (t.c3(a, pair(b, c)) + t.c3(b, pair(a, c)) + t.c3(c, pair(a, b))) / 36;
}

double VolumePolynomial::value(const Eigen::VectorXd& beta, Eigen::RowVectorXd* gradient) const {
  const Eigen::Index k = linear_.size();
  if (beta.size() > k)
    throw Error(ErrorKind::InvalidArgument,
                "beta has " + std::to_string(beta.size()) + " values; the volume polynomial has " + std::to_string(k),
                "beta");
  if (!beta.allFinite()) throw Error(ErrorKind::InvalidArgument, "beta contains NaN or infinity", "beta");
  Eigen::VectorXd b = Eigen::VectorXd::Zero(k);
  b.head(beta.size()) = beta;
  const Eigen::VectorXd cubic_b = cubic_ * b;  // M(l, m) = Σ_k c_klm β_k, at l + K·m
  const Eigen::VectorXd mb = Eigen::Map<const Eigen::MatrixXd>(cubic_b.data(), k, k) * b;
  const Eigen::VectorXd qb = quadratic_ * b;
  if (gradient) *gradient = (linear_ + 2 * qb + 3 * mb).transpose();
  return constant_ + linear_.dot(b) + b.dot(qb) + b.dot(mb);
}

}  // namespace caliper
