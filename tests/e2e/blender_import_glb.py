# Imports Caliper .glb and .fbx avatars into Blender (headless) with the importers' default
# options and checks what a user would get: one armature with the model's joints and the root
# bone as bones, one mesh deformed by it through an Armature modifier, a vertex group per bone
# that moves vertices, weights summing to 1, the rest shape unchanged by the import, each bone
# pointing at its child, and a bent elbow that moves the forearm without tearing the mesh.
#
#   blender -b --factory-startup --python tests/e2e/blender_import_glb.py -- a.glb [--shape-keys=N] b.fbx ...
#
# --shape-keys=N: the files after it were written with --morphs and must import with N shape
# keys shape_0 … shape_N−1 (after Blender's Basis), all at 0, each moving the body a little;
# files before it (or after --shape-keys=0) must have none.
# Prints one JSON line per file; exits 1 if any check fails.
import json
import math
import sys

import numpy

numpy.bool = bool  # Debian's numpy lacks the alias Blender 3.4's glTF importer still uses

import bpy  # noqa: E402


def check(path, shape_keys):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    if path.lower().endswith(".fbx"):
        bpy.ops.import_scene.fbx(filepath=path)
    else:
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
    # Every group is a bone. The FBX importer makes groups only for bones that weigh some vertex,
    # so the root bone and (on the built-in body) SMPL's knuckle joints, which are never among a
    # vertex's 4 largest weights, may have none: at most 3 bones without a group.
    if not set(groups) <= set(bones) or len(groups) < len(bones) - 3:
        problems.append(f"vertex groups differ from bones: {sorted(set(bones) ^ set(groups))}")
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
    problems += bone_problems(arm)
    problems += bend_problems(arm, mesh)
    problems += shape_key_problems(mesh, shape_keys)
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
        "shape_keys": len(mesh.data.shape_keys.key_blocks) - 1 if mesh.data.shape_keys else 0,
    }


def bone_problems(arm):
    """A bone with one child points at it (within 1°)."""
    out = []
    for b in arm.data.bones:
        if len(b.children) != 1:
            continue
        child = b.children[0]
        to_child = child.head_local - b.head_local
        if to_child.length < 1e-4:
            continue
        angle = math.degrees((b.tail_local - b.head_local).angle(to_child))
        if angle > 1.0:
            out.append(f"bone {b.name} points {angle:.1f}° away from {child.name}")
    return out


def shape_key_problems(mesh, expected):
    """The --morphs blend shapes: Basis, then shape_0 … shape_{expected-1}, all at 0; each key at
    1 moves some vertex by more than a millimetre and none by more than half a metre (one SD of
    a body shape direction)."""
    keys = mesh.data.shape_keys.key_blocks if mesh.data.shape_keys else []
    to_world = mesh.matrix_world.to_3x3()
    names = [k.name for k in keys]
    wanted = ["Basis"] + [f"shape_{k}" for k in range(expected)] if expected else []
    if names != wanted:
        return [f"shape keys {names[:4]}… ({len(names)}), expected {wanted[:4]}… ({len(wanted)})"]
    out = []
    for key in keys[1:]:
        if key.value != 0.0:
            out.append(f"shape key {key.name} is at {key.value}, not 0")
        # In metres whatever the file's unit (a centimetre FBX comes in with its objects scaled).
        moved = max((to_world @ (a.co - b.co)).length for a, b in zip(key.data, keys[0].data))
        if not 1e-3 < moved < 0.5:
            out.append(f"shape key {key.name} moves a vertex at most {moved:.4f} m")
    return out


def bend_problems(arm, mesh):
    """Bends the left elbow 60°: the hand must move, no vertex may fly off (an inconsistent
    bind pose shows as vertices thrown metres away)."""
    names = {"left_elbow", "LeftLowerArm"}
    elbow = next((b for b in arm.pose.bones if b.name in names), None)
    if elbow is None:
        return ["no left_elbow / LeftLowerArm bone"]
    depsgraph = bpy.context.evaluated_depsgraph_get()
    before = [v.co.copy() for v in mesh.evaluated_get(depsgraph).to_mesh().vertices]
    elbow.rotation_mode = "XYZ"
    elbow.rotation_euler = (0.0, 0.0, math.radians(60))
    bpy.context.view_layer.update()
    depsgraph = bpy.context.evaluated_depsgraph_get()
    after = [v.co.copy() for v in mesh.evaluated_get(depsgraph).to_mesh().vertices]
    elbow.rotation_euler = (0.0, 0.0, 0.0)
    bpy.context.view_layer.update()
    to_world = mesh.matrix_world.to_3x3()  # metres whatever the file's unit
    moved = sorted((to_world @ (a - b)).length for a, b in zip(after, before))
    out = []
    if moved[-1] < 0.05:
        out.append(f"bending the elbow moved no vertex more than {moved[-1]:.3f} m")
    if moved[-1] > 1.0:
        out.append(f"bending the elbow threw a vertex {moved[-1]:.2f} m")
    if sum(1 for m in moved if m > 1e-4) > len(moved) // 4:
        out.append("bending the elbow moved more than a quarter of the body")
    return out


def main():
    args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    files = [a for a in args if not a.startswith("--shape-keys=")]
    if not files:
        print("usage: blender -b --factory-startup --python blender_import_glb.py -- FILE.glb...", file=sys.stderr)
        sys.exit(2)
    ok = True
    shape_keys = 0
    for f in args:
        if f.startswith("--shape-keys="):
            shape_keys = int(f.split("=", 1)[1])
            continue
        try:
            result = check(f, shape_keys)
        except Exception as e:  # an importer failure is a failed check, not a crash
            result = {"file": f, "ok": False, "problems": [f"import failed: {e}"]}
        ok = ok and result["ok"]
        print(json.dumps(result))
    sys.exit(0 if ok else 1)


main()
