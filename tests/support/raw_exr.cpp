#include "tests/support/raw_exr.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>

#include <vector>

namespace candela {

void write_exr_as_is(const Image& image, const std::string& path) {
    Imf::Header header(image.width(), image.height());
    header.compression() = Imf::ZIP_COMPRESSION;
    for (const auto& [key, value] : image.metadata)
        if (header.find(key) == header.end()) header.insert(key, Imf::StringAttribute(value));
    std::vector<float> data = image.data();
    const size_t channels = size_t(image.channel_count());
    Imf::FrameBuffer frame;
    for (size_t c = 0; c < channels; ++c) {
        header.channels().insert(image.channels()[c], Imf::Channel(Imf::FLOAT));
        frame.insert(image.channels()[c], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(data.data() + c), sizeof(float) * channels,
                                                     sizeof(float) * channels * size_t(image.width())));
    }
    Imf::OutputFile file(path.c_str(), header);
    file.setFrameBuffer(frame);
    file.writePixels(image.height());
}

}  // namespace candela
