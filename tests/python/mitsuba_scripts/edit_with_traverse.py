# Written like Mitsuba 3's "editing a scene" tutorial (list the parameters, change one, update,
# render again); the only change for Candela is the import line.
import candela.mitsuba as mi

mi.set_variant("scalar_rgb")

scene = mi.load_file("scenes/cbox.xml", res=32)
original = mi.render(scene, spp=16)

# The scene's parameters, by name.
params = mi.traverse(scene)
print(params)

# Keep the red wall's colour, paint it blue, and let the scene know.
key = "red.reflectance.value"
param_ref = mi.Color3f(params[key])
params[key] = mi.Color3f(0.01, 0.2, 0.9)
params.update()

image = mi.render(scene, spp=16)
mi.util.write_bitmap("blue_wall.exr", image)
bitmap = mi.Bitmap(image).convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.UInt8, srgb_gamma=True)
bitmap.write("blue_wall.png")

# Back to the original colour, and a wider view.
params[key] = param_ref
params["PerspectiveCamera.x_fov"] = 50.0
params.update()
mi.util.write_bitmap("wide.exr", mi.render(scene, spp=16))
print("done")
