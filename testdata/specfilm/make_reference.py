"""Renders bands.xml with Mitsuba 3.9.1 `scalar_spectral` into bands.exr: the mean of four
seeds at 4096 spp each (float32, one channel per band, as its specfilm writes them).

    python make_reference.py   # needs `pip install mitsuba==3.9.1 numpy`
"""
import os
import numpy as np
import mitsuba as mi

mi.set_variant("scalar_spectral")
here = os.path.dirname(os.path.abspath(__file__))
scene = mi.load_file(os.path.join(here, "bands.xml"))
film = scene.sensors()[0].film()
images = []
for seed in range(4):
    mi.render(scene, spp=4096, seed=seed)
    bitmap = film.bitmap()
    names = [f.name for f in bitmap.struct_()]
    images.append(np.array(bitmap, dtype=np.float64))
mean = np.mean(images, axis=0).astype(np.float32)
out = mi.Bitmap(mean, mi.Bitmap.PixelFormat.MultiChannel, channel_names=names)
out.write(os.path.join(here, "bands.exr"))
print(names, mean.mean(axis=(0, 1)))
