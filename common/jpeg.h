// Small JPEGs of a tile's picture for the wall's dashboard (docs/wall.md), by libturbojpeg.
#pragma once

#include <string>

#include "common/image.h"

namespace glcast::slave {

// `image` (RGBA, rows top to bottom) scaled down by a whole factor to at most `max_width` pixels
// wide (averaging each block), as a baseline JPEG of `quality` (1-100). False with `error`.
bool thumbnail_jpeg(const Image& image, int max_width, int quality, std::string& jpeg, std::string& error);

}  // namespace glcast::slave
