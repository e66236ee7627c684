// A picture of a UV layout: every UV triangle's edges drawn into a square image, so a person can
// see the islands, their packing and their distortion (`caliper model uv-atlas`).
#pragma once
#include <string>

#include "caliper/body/mesh.h"

namespace caliper {

struct UvAtlasOptions {
  int size = 1024;  // pixels, width = height
  bool fill = true; // shade each triangle's interior (light grey) under the edges
};

// PNG bytes (8-bit RGB, size×size) of `uv` (U×2) and `uv_faces` (F×3 indices into uv): the unit
// square [0, 1]² with v up (OBJ's convention; the image's top row is v = 1), a white background,
// triangle interiors light grey, edges dark. Throws Error(InvalidArgument) for a size outside
// [16, 8192], non-finite coordinates or out-of-range indices.
std::string render_uv_atlas_png(const UvCoordinates& uv, const Faces& uv_faces, const UvAtlasOptions& options = {});

}  // namespace caliper
