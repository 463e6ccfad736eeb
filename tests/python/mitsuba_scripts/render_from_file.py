# Written like Mitsuba 3's quickstart tutorial (render a scene from a file, write the image); the
# only change for Candela is the import line.
import candela.mitsuba as mi

# Choose the variant: scalar RGB on the CPU.
mi.set_variant("scalar_rgb")

# Load the scene; keyword arguments set the file's $parameters (a small image keeps this quick).
scene = mi.load_file("scenes/cbox.xml", res=32)

# Render it with 16 samples per pixel: a linear RGB image, an H x W x 3 array.
image = mi.render(scene, spp=16)
print("rendered", image.shape)

# PNG: tonemapped to 8-bit sRGB; EXR: the linear values.
mi.util.write_bitmap("my_first_render.png", image)
mi.util.write_bitmap("my_first_render.exr", image)
