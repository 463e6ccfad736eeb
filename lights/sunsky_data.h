#pragma once
// The Hosek-Wilkie sky and sun model data that the sunsky emitter evaluates, compiled into the
// program (lights/sunsky_data.cpp). The files are Mitsuba 3's data/sunsky (lights/data/sunsky,
// with their licence and source); tensors, row-major, last index fastest:
//
//   sunsky_datasets.bin
//     sky_params_rgb   float64 [10 turbidity, 2 albedo, 6 elevation control points, 3 channels, 9]
//     sky_rad_rgb      float64 [10, 2, 6, 3]
//     sky_params_spec  float64 [10, 2, 6, 11 wavelengths, 9]
//     sky_rad_spec     float64 [10, 2, 6, 11]
//     sun_rad_rgb      float64 [10 turbidity, 45 elevation segments, 3, 4 polynomial, 6 limb]
//     sun_rad_spec     float64 [10, 45, 11, 4]
//     sun_ld_spec      float64 [11, 6] limb-darkening polynomial per wavelength
//   sampling_data.bin
//     sun_irradiance   float32 [10 turbidity, 30 sun elevations (2, 5, ... 89 degrees), 11]
//     sky_irradiance   float32 [10, 30, 11]
//
// The 11 wavelengths are 320, 360, ... 720 nm; turbidity runs 1 to 10.

#include "core/tensor_file.h"

namespace candela {

const TensorFile& sunsky_datasets();
const TensorFile& sunsky_sampling_data();

}  // namespace candela
