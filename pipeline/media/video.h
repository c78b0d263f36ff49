// Video and frame-sequence input/output through ffmpeg, run as a child process (never linked).
//
// ffmpeg is found as $SMOKESVD_FFMPEG if set, else `ffmpeg` on PATH; ffprobe next to it. Without ffmpeg every
// video function throws an Error saying so; PNG sequences need no ffmpeg. Frames are gray, values in [0, 1],
// row 0 at the top (pipeline/media/image.h).
#pragma once

#include <filesystem>
#include <optional>
#include <vector>

#include "pipeline/media/image.h"

namespace smokesvd::media {

struct VideoInfo {
  int width = 0, height = 0;
  double frameRate = 0;
  int frameCount = 0;  // 0 when the container does not say
};

// The ffmpeg executable, or nothing if it cannot be found.
std::optional<std::filesystem::path> findFfmpeg();
// The ffmpeg executable; else throws Error("<forWhat>: ...") saying why (not on PATH, or SMOKESVD_FFMPEG
// names something that is not an executable file) and what to do.
std::filesystem::path requireFfmpeg(const std::string& forWhat);

VideoInfo probeVideo(const std::filesystem::path& path);
// Frames [first, first + count) of a video (count < 0: to the end), decoded to gray.
std::vector<Image> readVideoFrames(const std::filesystem::path& path, int first = 0, int count = -1);
// Encodes gray frames (all one size) as H.264 mp4 at `frameRate`; written to a temporary name, then renamed.
void writeVideo(const std::filesystem::path& path, const std::vector<Image>& frames, double frameRate = 30);

// Frame input for the pipeline: a folder of PNG files (sorted by name) or a video file.
std::vector<Image> readFrames(const std::filesystem::path& path, int first = 0, int count = -1);

}  // namespace smokesvd::media
