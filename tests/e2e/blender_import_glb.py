# Imports Caliper .glb avatars into Blender (headless) and checks what a user would get:
# one armature with the model's joints as bones, one mesh parented to it through an Armature
# modifier, one vertex group per joint, and the rest shape unchanged by the import.
#
#   blender -b --factory-startup --python tests/e2e/blender_import_glb.py -- a.glb [b.glb ...]
#
# Prints one JSON line per file; exits 1 if any check fails.
import json
import sys

import numpy

numpy.bool = bool  # Debian's numpy lacks the alias Blender 3.4's glTF importer still uses

import bpy  # noqa: E402


def check(path):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=path)
    armatures = [o for o in bpy.data.objects if o.type == "ARMATURE"]
    meshes = [o for o in bpy.data.objects if o.type == "MESH"]
    problems = []
    if len(armatures) != 1:
        problems.append(f"{len(armatures)} armatures")
    if len(meshes) != 1:
        problems.append(f"{len(meshes)} meshes")
    if problems:
        return {"file": path, "ok": False, "problems": problems}
    arm, mesh = armatures[0], meshes[0]
    mods = [m for m in mesh.modifiers if m.type == "ARMATURE"]
    if not mods or mods[0].object != arm:
        problems.append("mesh has no Armature modifier pointing at the armature")
    bones = [b.name for b in arm.data.bones]
    groups = [g.name for g in mesh.vertex_groups]
    if sorted(groups) != sorted(bones):
        problems.append("vertex groups differ from bones")
    # Every vertex's weights sum to 1 (glTF WEIGHTS_0 survived the import).
    worst = 0.0
    for v in mesh.data.vertices:
        worst = max(worst, abs(sum(g.weight for g in v.groups) - 1.0))
    if worst > 1e-4:
        problems.append(f"a vertex's weights sum off 1 by {worst:.2e}")
    # Evaluated (skinned) rest shape equals the stored vertices: bind pose is consistent.
    depsgraph = bpy.context.evaluated_depsgraph_get()
    evaluated = mesh.evaluated_get(depsgraph).to_mesh()
    moved = max(
        ((mesh.matrix_world @ a.co) - (mesh.matrix_world @ b.co)).length
        for a, b in zip(mesh.data.vertices, evaluated.vertices)
    )
    if moved > 1e-4:
        problems.append(f"skinning in the rest pose moves a vertex by {moved:.2e} m")
    zs = [(mesh.matrix_world @ v.co).z for v in mesh.data.vertices]  # Blender is Z-up
    return {
        "file": path,
        "ok": not problems,
        "problems": problems,
        "bones": len(bones),
        "vertices": len(mesh.data.vertices),
        "faces": len(mesh.data.polygons),
        "height_m": round(max(zs) - min(zs), 4),
        "lowest_z_m": round(min(zs), 4),
        "armature_object": arm.name,
        "mesh_parent": mesh.parent.name if mesh.parent else None,
    }


def main():
    files = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if not files:
        print("usage: blender -b --factory-startup --python blender_import_glb.py -- FILE.glb...", file=sys.stderr)
        sys.exit(2)
    ok = True
    for f in files:
        try:
            result = check(f)
        except Exception as e:  # an importer failure is a failed check, not a crash
            result = {"file": f, "ok": False, "problems": [f"import failed: {e}"]}
        ok = ok and result["ok"]
        print(json.dumps(result))
    sys.exit(0 if ok else 1)


main()
