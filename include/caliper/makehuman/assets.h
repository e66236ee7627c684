// MakeHuman's CC0 body assets in the MPFB2 folder layout: the hm08 base mesh, gzipped
// morph targets, the macro combination rule, the local `measure-*` modifiers, and the 31-bone
// `cmu_mb` rig with its skinning weights. Format facts are those of the assets' README; no
// MakeHuman or MPFB2 code is involved. Files are untrusted: every reader throws caliper::Error
// naming the file (and the line) on anything it cannot read.
#pragma once
#include <Eigen/Core>
#include <map>
#include <string>
#include <vector>

#include "caliper/body/mesh.h"

namespace caliper::makehuman {

// hm08: vertices [0, 13380) are the body (a closed genus-0 surface); the rest are helpers
// (eyes, teeth, tights, hair …) and the 8-vertex joint cubes.
constexpr int kBodyVertexCount = 13380;

// A morph target: sparse displacements of the base mesh, metres (files store decimetres).
struct Target {
  std::string name;                 // file name without ".target.gz", e.g. "universal-female-young-maxmuscle-averageweight"
  std::string path;
  std::vector<int> indices;         // vertex indices, 0-based, < the base mesh's vertex count
  std::vector<Eigen::Vector3f> deltas;
};

// Reads one `.target.gz`: gzipped text, one `index dx dy dz` line per displaced vertex.
// Throws Error(Io) if the file cannot be opened, Error(Format) naming the file and line for a
// stream that is not gzip or is damaged, a non-number, a non-finite value, or an index outside
// [0, vertex_count).
Target read_target(const std::string& path, int vertex_count);

struct BaseMesh {
  Vertices vertices;        // all hm08 vertices (body, helpers, joint cubes), metres, A-pose, as in the file
  Faces body_faces;         // triangles of the body only (quads split), outward, indices < kBodyVertexCount
  // The body's texture coordinates from the file's `vt` lines (OBJ convention, v up), when every
  // body face corner has one in [0, 1]; else both empty. body_uv_faces rows match body_faces
  // (same split, same corner order); body_uv keeps only the UVs the body uses, in file order.
  UvCoordinates body_uv;
  Faces body_uv_faces;
  std::map<std::string, std::vector<int>> groups;  // vertex groups by name ("joint-l-elbow" → its 8 vertices)
  std::vector<int> mirror;  // mirror[v] = the vertex mirroring v across x = 0 (itself on the midline)
};

// Reads 3dobjs/base.obj and mesh_metadata/{basemesh_vertex_groups.json, hm08.mirror}. Throws
// Error(Format) if the body part is not closed and manifold once the helpers are dropped.
BaseMesh read_base_mesh(const std::string& assets_dir);

// A bone of the rig: its head is the joint it rotates about.
struct Bone {
  std::string name;
  std::string parent;                     // empty for the root
  std::vector<int> head_vertices;         // joint = mean of these (CUBE: the cube's 8; VERTEX: one; MEAN: listed)
  std::vector<int> tail_vertices;
};

struct Rig {
  std::vector<Bone> bones;                // parents before children
  // Skinning weights, vertex → (bone index, weight), normalised to sum 1 over the vertex.
  std::vector<std::vector<std::pair<int, float>>> weights;  // one entry per base-mesh vertex
  int bone_index(const std::string& name) const;            // -1 if absent
};

// Reads rigs/standard/rig.<name>.json and weights.<name>.json, resolving CUBE joints through
// the mesh's vertex groups. Throws Error(Format) naming the bone for an unknown cube, strategy
// or vertex index, and for a body vertex without weights.
Rig read_rig(const std::string& assets_dir, const BaseMesh& mesh, const std::string& name = "cmu_mb");

// A target the loader did not trust, and why (it is left out of every body).
struct TargetProblem {
  std::string name;   // target name, e.g. "female-old-maxmuscle-maxweight-minheight"
  std::string reason;
};

struct Assets {
  std::string dir;
  BaseMesh mesh;
  Rig rig;
  std::vector<Target> macro_targets;     // race/gender/age, universal, height, proportions, breast (cup/firmness)
  std::vector<Target> modifier_targets;  // measure-*-{decr,incr}
  std::vector<TargetProblem> problems;   // skipped targets
};

struct LoadOptions {
  // Leave out macro targets whose ages never occur (adults: no "baby"). Purely a speed-up.
  bool skip_baby = true;
};

// Loads everything the builder needs from an MPFB2-layout folder: the data folder itself
// (3dobjs/, mesh_metadata/, targets/, rigs/), a clone of the MPFB2 repository (its data is
// src/mpfb/data) or an unpacked archive of it (one wrapping folder); `Assets::dir` is the data
// folder found. Throws Error(Io) naming the
// path for a missing folder or file (and says what a right folder contains), Error(Format) for
// a damaged file. A target that reads cleanly but has far fewer entries than its siblings
// (truncated at the source) is skipped and listed in `problems` rather than trusted.
Assets load_assets(const std::string& assets_dir, const LoadOptions& options = {});

}  // namespace caliper::makehuman
