import sys, numpy as np
import bpy
# blender -b --python blender_side_by_side.py -- OUT.png IN.png ...: blender_render.py's pictures
# (480×640) side by side as one RGB picture, each cropped to the 400×540 around the body (40 px
# off each side, 30 px off the top, 70 off the bottom).
out, *ins = sys.argv[sys.argv.index("--") + 1:]
def crop(path):
    im = bpy.data.images.load(path)
    w, h = im.size
    if (w, h) != (480, 640): sys.exit(f"{path}: {w}x{h}, expected blender_render.py's 480x640")
    a = np.empty(w * h * 4, np.float32)
    im.pixels.foreach_get(a)
    return a.reshape(h, w, 4)[70:610, 40:440]  # rows counted from the bottom, as Blender stores them
a = np.concatenate([crop(p) for p in ins], axis=1)
a[..., 3] = 1.0
im = bpy.data.images.new("side_by_side", a.shape[1], a.shape[0], alpha=False)
im.pixels.foreach_set(a.ravel())
scene = bpy.context.scene
scene.render.image_settings.file_format = "PNG"
scene.render.image_settings.color_mode = "RGB"
im.save_render(out, scene=scene)
