#pragma once
// PNG reading and writing for the TUM layout. Errors (InputError) name the file and the problem.

#include <string>

#include "vocal/core/image.h"

namespace vocal {

// 8-bit colour (3 channels) or grey PNG, returned as RGB.
ColorImage readColorPng(const std::string& path);
void writeColorPng(const std::string& path, const ColorImage& image);

// 16-bit single-channel PNG with `depth_scale` units per metre (TUM: 5000); 0 means no measurement.
DepthImage readDepthPng(const std::string& path, double depth_scale);
// Rounds to the nearest unit; invalid pixels and depths beyond the 16-bit range are written as 0.
void writeDepthPng(const std::string& path, const DepthImage& depth, double depth_scale);

}  // namespace vocal
