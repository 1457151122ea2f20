// One row of the BOP results CSV as text, for writers that append rows as they come (the
// results journal) rather than a whole file at once (WriteResultsCsv).
#pragma once

#include <string>
#include <string_view>

#include "mcpose/results.h"

namespace mcpose::io {

// "scene_id,im_id,obj_id,score,R,t,time" without the line end, as WriteResultsCsv writes it.
std::string ResultsCsvRow(const PoseResult& r);
// Parses one row; empty on success, else the problem ("R is not a rotation: ...").
std::string ParseResultsCsvRow(std::string_view line, PoseResult* r);
std::string_view ResultsCsvHeader();

}  // namespace mcpose::io
