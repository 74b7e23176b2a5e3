"""Extracts the spectral tables of Mitsuba 3.9.1's `sunsky` emitter into `sunsky_spectral.bin`.

The Hosek-Wilkie sky and sun tables ship with Mitsuba (pip `mitsuba==3.9.1`) as
`mitsuba/data/sunsky/sunsky_datasets.bin` (float64) and `sampling_data.bin` (float32), under the
3-clause BSD licence of the Hosek-Wilkie model (LICENSE, next to this script). gonio's `sunsky`
needs only their spectral fields, which Mitsuba rounds to float32 when it loads them; this writes
those fields, rounded the same way, into one Mitsuba tensor file that gonio embeds:

    sky_params_spec  [10 turbidity, 2 albedo, 6 control points, 11 wavelengths, 9 coefficients]
    sky_rad_spec     [10, 2, 6, 11]
    sun_rad_spec     [10 turbidity, 45 segments, 11 wavelengths, 4 powers]
    sun_ld_spec      [11 wavelengths, 6 powers]
    sun_irradiance   [10 turbidity, 30 sun elevations (2 + 3 i degrees), 11 wavelengths]

Usage: python make_data.py   (with the `mitsuba` module importable; rewrites the file in place)
"""
import os

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_spectral")
SRC = os.path.join(os.path.dirname(mi.__file__), "data", "sunsky")
HERE = os.path.dirname(os.path.abspath(__file__))


def field(tf, name):
    # Rounded to float32 as Mitsuba's `load_field` does (a float64 field read as `TensorXf`).
    fld = tf[name]
    wide = "Float64" in repr(fld.dtype)
    return np.array(fld.to(mi.ScalarTensorXf64 if wide else mi.ScalarTensorXf)).astype(np.float32)


def main():
    datasets = mi.TensorFile(os.path.join(SRC, "sunsky_datasets.bin"))
    sampling = mi.TensorFile(os.path.join(SRC, "sampling_data.bin"))
    fields = {name: field(datasets, name)
              for name in ["sky_params_spec", "sky_rad_spec", "sun_rad_spec", "sun_ld_spec"]}
    fields["sun_irradiance"] = field(sampling, "sun_irradiance")
    for name, v in fields.items():
        print(name, v.shape, v.dtype)
    mi.tensor_io.write(os.path.join(HERE, "sunsky_spectral.bin"), **fields)


if __name__ == "__main__":
    main()
