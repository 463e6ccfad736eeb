// The sunsky emitter's data files (lights/sunsky_data.h), compiled in (core/embedded_file.h):
// CMakeLists.txt defines their paths and MD5s.

#include "lights/sunsky_data.h"

#include "core/embedded_file.h"

#include <vector>

#if !defined(CANDELA_SUNSKY_DATASETS) || !defined(CANDELA_SUNSKY_SAMPLING) || !defined(CANDELA_SUNSKY_MD5)
#error "CMakeLists.txt defines CANDELA_SUNSKY_DATASETS, CANDELA_SUNSKY_SAMPLING and CANDELA_SUNSKY_MD5"
#endif

CANDELA_EMBED_FILE(candela_sunsky_datasets, CANDELA_SUNSKY_DATASETS);
CANDELA_EMBED_FILE(candela_sunsky_sampling, CANDELA_SUNSKY_SAMPLING);
CANDELA_EMBEDDED_FILE_SYMBOLS(candela_sunsky_datasets)
CANDELA_EMBEDDED_FILE_SYMBOLS(candela_sunsky_sampling)

namespace candela {

const TensorFile& sunsky_datasets() {
    static const TensorFile file("the compiled-in sunsky_datasets.bin",
                                 std::vector<uint8_t>(candela_sunsky_datasets_begin, candela_sunsky_datasets_end));
    return file;
}

const TensorFile& sunsky_sampling_data() {
    static const TensorFile file("the compiled-in sampling_data.bin",
                                 std::vector<uint8_t>(candela_sunsky_sampling_begin, candela_sunsky_sampling_end));
    return file;
}

}  // namespace candela
