#include "core/sampler.h"

#include "core/error.h"

namespace candela {

void Sampler::set_sample_count(int spp) {
    if (std::string problem = sample_count_problem(spp); !problem.empty()) throw InternalError(to_string() + " sampler: " + problem);
    sample_count_ = round_sample_count(spp);
}

void Sampler::set_film(const Vec2i& size, int border) {
    film_size_ = glm::max(size, Vec2i(1));
    film_border_ = std::max(border, 0);
    film_changed();
}

void Sampler::refuse_start(const Vec2i& pixel, uint32_t index) const {
    throw InternalError(to_string() + " sampler asked for sample " + std::to_string(index) + " of pixel (" + std::to_string(pixel.x) +
                        ", " + std::to_string(pixel.y) + "), outside its " + std::to_string(sample_count_) + " samples per pixel of a " +
                        std::to_string(film_size_.x) + " x " + std::to_string(film_size_.y) + " film with a border of " +
                        std::to_string(film_border_) + " pixels");
}

std::string sample_count_problem(int64_t spp) {
    if (spp < 1) return "the sample count must be at least 1 (got " + std::to_string(spp) + ")";
    if (spp > MaxSampleCount)
        return "the sample count must be at most 2^30 = " + std::to_string(MaxSampleCount) + " (got " + std::to_string(spp) + ")";
    return "";
}

}  // namespace candela
