// Model files: Caliper's native .npz format (docs/model-format.md) and SMPL / SMPL-X .npz
// files as users have them (arrays in SPEC.md). Models are found by name in the models folder.
#pragma once
#include <optional>
#include <string>

#include "caliper/body/body_model.h"

namespace caliper {

void save_model(const BodyModel& model, const std::string& path);
BodyModel load_native_model(const std::string& path);

struct SmplLoadOptions {
  int shape_count = 10;  // how many shape directions to keep (1..400, ≤ what the file has)
  Sex sex = Sex::Neutral;
  std::string name;      // defaults to the file name
};
// SMPL / SMPL-X: v_template, shapedirs (N×3×K), J_regressor (dense J×N, or sparse as
// J_regressor_{data,indices,indptr,shape} CSR/CSC), weights (N×J), kintree_table (2×J), f.
// Landmarks and measurement definitions for SMPL's 6890-vertex topology are attached
// (landmarks/smpl.json) when the topology matches.
BodyModel load_smpl_model(const std::string& path, const SmplLoadOptions& options = {});

// Loads by file path (native or SMPL, detected by the arrays inside) or by model name
// ("mannequin", "mannequin-female", …) looked up in the models folder. The sex picks the
// variant for a family name: "mannequin" + female → "mannequin-female".
// Whose file it is decides the errors' origin (errors.h): a path is the caller's, a model found by
// name is the installation's, so its damage is ErrorOrigin::Installation (CLI exit 5, HTTP 500),
// also when found later in its contents (BodyModelData::supplied_by).
BodyModel load_model(const std::string& name_or_path, Sex sex);

// Landmarks and measurement definitions for SMPL's 6890-vertex topology: the JSON text of
// landmarks/smpl.json, compiled into the library so installed binaries need no data folder.
const std::string& smpl_landmarks_json();

// Folder of the models found by name (docs/cli.md "Where Caliper finds its files"):
// $CALIPER_MODELS_DIR if set, else `models/` beside the binary holding the library (the Python
// package's module, docs/python.md), else `share/caliper/models` of the running program's
// installation (installed_data_dir), else the source tree's `models/` it was built from.
std::string models_dir();

// `<prefix>/share/caliper` of an installed program, found from the running executable's own path
// (`<prefix>/bin/…`, so a moved installation still finds it); "" when the program does not run
// from such a tree (e.g. from the build folder).
std::string installed_data_dir();

}  // namespace caliper
