// The 21 YCB-Video object names, in cls_index order (= BOP ycbv obj_id): the one place they
// are spelled out.
#pragma once

#include <string>
#include <vector>

namespace mcpose::io {

// Element k - 1 is the name of obj_id k ("002_master_chef_can" for 1, ..., "061_foam_brick"
// for 21).
const std::vector<std::string>& YcbvClassNames();

}  // namespace mcpose::io
