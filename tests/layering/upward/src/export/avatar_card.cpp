// A deliberately bad export file (tests/CMakeLists.txt, layering_*): export sits below the
// avatar, so it may not include avatar.h.
#include "caliper/export/gltf.h"
#include "caliper/avatar.h"
