import sys, math, numpy
numpy.bool = bool
import bpy
from mathutils import Vector
# blender -b --python blender_render.py -- FILE OUT.png ENGINE [shape_k=VALUE ...]: the avatar
# with a bent elbow and knee, and the named shape keys (a --morphs file's) moved to VALUE.
args = sys.argv[sys.argv.index("--")+1:]
f, out, engine = args[0], args[1], args[2]
shape_values = dict((k, float(v)) for k, v in (a.split("=", 1) for a in args[3:]))
bpy.ops.wm.read_factory_settings(use_empty=True)
if f.endswith(".fbx"):
    bpy.ops.import_scene.fbx(filepath=f)
else:
    bpy.ops.import_scene.gltf(filepath=f)
arm = [o for o in bpy.data.objects if o.type == "ARMATURE"][0]
for name in ("left_elbow", "LeftLowerArm"):
    if name in arm.pose.bones:
        pb = arm.pose.bones[name]; pb.rotation_mode = "XYZ"; pb.rotation_euler = (0, 0, math.radians(70))
for name in ("right_knee", "RightLowerLeg"):
    if name in arm.pose.bones:
        pb = arm.pose.bones[name]; pb.rotation_mode = "XYZ"; pb.rotation_euler = (math.radians(-40), 0, 0)
for o in bpy.data.objects:
    if o.type == "MESH" and o.data.shape_keys:
        for name, value in shape_values.items():
            key = o.data.shape_keys.key_blocks[name]
            key.slider_min, key.value = min(key.slider_min, value), value
scene = bpy.context.scene
cam = bpy.data.objects.new("cam", bpy.data.cameras.new("cam"))
scene.collection.objects.link(cam)
cam.location = (1.25, -4.4, 0.95)
cam.rotation_euler = (math.radians(88), 0, math.radians(16))
cam.data.lens = 62
scene.camera = cam
light = bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN"))
light.data.energy = 4
light.rotation_euler = (math.radians(45), 0, math.radians(30))
scene.collection.objects.link(light)
world = bpy.data.worlds.new("w"); world.color = (0.9, 0.9, 0.9); scene.world = world
world.use_nodes = True
world.node_tree.nodes["Background"].inputs[0].default_value = (0.85, 0.85, 0.85, 1)
# A dimmer sky: at full strength it lit the body evenly from every side and washed its shape out.
world.node_tree.nodes["Background"].inputs[1].default_value = 0.35
scene.render.engine = engine
if engine == "CYCLES":
    scene.cycles.samples = 16
    scene.cycles.device = "CPU"
scene.render.resolution_x, scene.render.resolution_y = 480, 640
scene.render.filepath = out
bpy.ops.render.render(write_still=True)
print("RENDERED", out)
