// One frame of an episode video: the cameras tiled with their names (render::MakeContactSheet)
// under a caption band that carries the episode's step and, once known, its outcome. Frames are
// RGB, and both sides are even, as the H.264 encoder's yuv420p needs.
#pragma once

#include <string>
#include <vector>

#include "render/image_io.h"

namespace tavis::batch::rollout {

// `views` must be non-empty with even sizes (ValidateVideoTileSize); `caption` holds the band's
// lines, top first (more than kCaptionLines are refused: the band's height is fixed, so every
// frame of a video has the same size).
render::RgbImage ComposeVideoFrame(const std::vector<render::LabelledImage>& views,
                                   const std::vector<std::string>& caption);

inline constexpr int kCaptionLines = 2;

// The frame size ComposeVideoFrame gives for `cameras` tiles of tile_width x tile_height.
std::pair<int, int> VideoFrameSize(int cameras, int tile_width, int tile_height);

}  // namespace tavis::batch::rollout
