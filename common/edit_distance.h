// Edit distance for "did you mean" hints (display config keys, effect parameter names).
#pragma once

#include <cstddef>
#include <string>

namespace glcast {

// Edits (insert, delete, replace, swap two neighbours) that turn a into b: "widht" -> "width" is
// 1; SIZE_MAX for strings over 64 characters.
size_t edit_distance(const std::string& a, const std::string& b);

}  // namespace glcast
