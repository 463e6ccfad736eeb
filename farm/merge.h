#pragma once
// Merging the parts of a split render (`candela merge`): the parts must belong to one render and
// must not overlap; what they leave out is reported with the command that renders it. The sums
// are added one part at a time, so memory is one image of sums plus one part, however many parts
// there are; a merge can also write a part (the union of its inputs) for a merge tree.

#include "farm/part_file.h"

#include <string>
#include <vector>

namespace candela {

struct MergeSet {
    RenderIdentity identity;
    std::vector<PartHeader> parts;
    std::vector<CoverageBox> missing;  // what image x [0, spp) the parts leave out
};

// Reads the parts' metadata (each path a part file, or a folder whose *.exr files are parts).
// InputError naming the files when one is not a part, belongs to another render (scene, seed,
// sampler, resolution, version, ...), or overlaps another.
MergeSet check_parts(const std::vector<std::string>& paths);

// The command that renders `box` of the render into `output`.
std::string render_command_for(const RenderIdentity& identity, const CoverageBox& box, const Vec2i& image, const std::string& output);
// One line per missing box: what is missing and the command that renders it (into the folder of
// the first part).
std::string describe_missing(const MergeSet& set);

// The final image: the parts' sums added in the order given and divided; with pieces missing,
// the mean of what there is (pixels no part covers are black), marked candela.partial.
Image merge_image(const MergeSet& set);
// All the parts as one part (coverage: the union of theirs) for a further merge.
void merge_into_part(const MergeSet& set, const std::string& output);

}  // namespace candela
