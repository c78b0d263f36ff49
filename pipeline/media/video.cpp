#include "pipeline/media/video.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

#include "nets/io/temporary_files.h"
#include "runtime/error.h"

namespace smokesvd::media {
namespace {

namespace fs = std::filesystem;

// A child process with its stdin and stdout as pipes and its stderr in a temporary file (so neither side can
// block on a full pipe). The destructor closes the pipes and reaps the child.
class ChildProcess {
 public:
  ChildProcess(const fs::path& program, const std::vector<std::string>& arguments) {
    stderrPath_ = fs::temp_directory_path() / ("smokesvd-child-" + std::to_string(::getpid()) + "-" +
                                               std::to_string(counter()++) + ".log");
    int toChild[2], fromChild[2];
    if (::pipe(toChild) != 0 || ::pipe(fromChild) != 0) throw Error("cannot create pipes for " + program.string());
    std::vector<std::string> argv = {program.string()};
    argv.insert(argv.end(), arguments.begin(), arguments.end());
    std::vector<char*> raw;
    for (std::string& a : argv) raw.push_back(a.data());
    raw.push_back(nullptr);
    const std::string logPath = stderrPath_.string();
    const std::string cannotRun = "cannot run " + program.string() + ": ";
    // A child that exits early must make our writes fail (EPIPE), not kill this process with SIGPIPE.
    static const bool sigpipeIgnored = std::signal(SIGPIPE, SIG_IGN) != SIG_ERR;
    (void)sigpipeIgnored;
    pid_ = ::fork();
    if (pid_ < 0) throw Error("cannot start " + program.string() + ": " + std::strerror(errno));
    if (pid_ == 0) {
      ::dup2(toChild[0], 0);
      ::dup2(fromChild[1], 1);
      const int log = ::open(logPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
      if (log >= 0) ::dup2(log, 2);
      for (int fd : {toChild[0], toChild[1], fromChild[0], fromChild[1]}) ::close(fd);
      ::execv(raw[0], raw.data());
      const char* reason = std::strerror(errno);
      [[maybe_unused]] ssize_t written = ::write(2, cannotRun.data(), cannotRun.size());
      written = ::write(2, reason, std::strlen(reason));
      ::_exit(127);
    }
    ::close(toChild[0]);
    ::close(fromChild[1]);
    in_ = toChild[1];
    out_ = fromChild[0];
  }
  ~ChildProcess() {
    closeInput();
    if (out_ >= 0) ::close(out_);
    if (pid_ > 0) {
      ::kill(pid_, SIGTERM);
      ::waitpid(pid_, nullptr, 0);
    }
    std::error_code ignored;
    fs::remove(stderrPath_, ignored);
  }
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  // Reads exactly `size` bytes unless the child's output ends first; returns the bytes read.
  std::size_t read(unsigned char* data, std::size_t size) {
    std::size_t done = 0;
    while (done < size) {
      const ssize_t n = ::read(out_, data + done, size - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) break;
      done += static_cast<std::size_t>(n);
    }
    return done;
  }
  std::string readAll() {
    std::string text;
    char buffer[4096];
    for (;;) {
      const ssize_t n = ::read(out_, buffer, sizeof buffer);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) break;
      text.append(buffer, static_cast<std::size_t>(n));
    }
    return text;
  }
  bool write(const unsigned char* data, std::size_t size) {
    std::size_t done = 0;
    while (done < size) {
      const ssize_t n = ::write(in_, data + done, size - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) return false;
      done += static_cast<std::size_t>(n);
    }
    return true;
  }
  void closeInput() {
    if (in_ >= 0) ::close(in_);
    in_ = -1;
  }
  // Waits for the child; returns its exit status (128 + signal when killed).
  int wait() {
    closeInput();
    int status = 0;
    ::waitpid(pid_, &status, 0);
    pid_ = -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  }
  // The last lines the child wrote to stderr, on one line.
  std::string errors() const {
    std::ifstream file(stderrPath_);
    std::string line, last;
    while (std::getline(file, line))
      if (!line.empty()) last = line;
    return last.empty() ? "no message" : last;
  }

 private:
  static int& counter() {
    static int value = 0;
    return value;
  }
  pid_t pid_ = -1;
  int in_ = -1, out_ = -1;
  fs::path stderrPath_;
};

void requireReadable(const fs::path& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file || fs::is_directory(path)) throw Error(path.string() + ": cannot open video file");
}

double parseRate(const std::string& text) {
  const auto slash = text.find('/');
  if (slash == std::string::npos) return std::atof(text.c_str());
  const double den = std::atof(text.c_str() + slash + 1);
  return den > 0 ? std::atof(text.substr(0, slash).c_str()) / den : 0.0;
}

bool isExecutableFile(const fs::path& path) {
  std::error_code error;
  return fs::is_regular_file(path, error) && ::access(path.c_str(), X_OK) == 0;
}

const char* configuredFfmpeg() {
  const char* configured = std::getenv("SMOKESVD_FFMPEG");
  return configured != nullptr && *configured != '\0' ? configured : nullptr;
}

}  // namespace

std::optional<fs::path> findFfmpeg() {
  if (const char* configured = configuredFfmpeg()) {
    if (isExecutableFile(configured)) return fs::path(configured);
    return std::nullopt;
  }
  const char* path = std::getenv("PATH");
  std::stringstream folders(path != nullptr ? path : "/usr/bin:/bin");
  std::string folder;
  while (std::getline(folders, folder, ':')) {
    const fs::path candidate = fs::path(folder.empty() ? "." : folder) / "ffmpeg";
    if (isExecutableFile(candidate)) return candidate;
  }
  return std::nullopt;
}

fs::path requireFfmpeg(const std::string& forWhat) {
  if (std::optional<fs::path> ffmpeg = findFfmpeg()) return *ffmpeg;
  if (const char* configured = configuredFfmpeg())
    throw Error(forWhat + ": SMOKESVD_FFMPEG=" + configured + " is not an executable file (set it to ffmpeg's path, "
                "or unset it to use the ffmpeg on PATH)");
  throw Error(forWhat + ": reading or writing video needs ffmpeg, which was not found on PATH (install it, e.g. "
              "apt-get install ffmpeg, or set SMOKESVD_FFMPEG to its path); PNG frame folders work without it");
}

VideoInfo probeVideo(const fs::path& path) {
  const fs::path ffmpeg = requireFfmpeg(path.string());
  requireReadable(path);
  const fs::path ffprobe = ffmpeg.parent_path() / "ffprobe";
  ChildProcess child(ffprobe, {"-v", "error", "-select_streams", "v:0", "-show_entries",
                               "stream=width,height,r_frame_rate,nb_frames", "-of", "default=noprint_wrappers=1",
                               path.string()});
  const std::string text = child.readAll();
  const int status = child.wait();
  VideoInfo info;
  std::stringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    const auto equals = line.find('=');
    if (equals == std::string::npos) continue;
    const std::string key = line.substr(0, equals), value = line.substr(equals + 1);
    if (key == "width") info.width = std::atoi(value.c_str());
    if (key == "height") info.height = std::atoi(value.c_str());
    if (key == "r_frame_rate") info.frameRate = parseRate(value);
    if (key == "nb_frames") info.frameCount = std::atoi(value.c_str());
  }
  if (status != 0 || info.width <= 0 || info.height <= 0)
    throw Error(path.string() + ": not a readable video (ffprobe: " + child.errors() + ")");
  return info;
}

std::vector<Image> readVideoFrames(const fs::path& path, int first, int count) {
  const VideoInfo info = probeVideo(path);
  const fs::path ffmpeg = requireFfmpeg(path.string());
  std::vector<std::string> arguments = {"-v", "error", "-nostdin"};
  if (first > 0 && info.frameRate > 0) {
    // Input seeking decodes from the keyframe before and drops frames earlier than the given time: half a
    // frame before frame `first` keeps exactly the frames from `first` on (constant frame rate).
    arguments.insert(arguments.end(), {"-ss", std::to_string((first - 0.5) / info.frameRate), "-i", path.string()});
  } else {
    arguments.insert(arguments.end(), {"-i", path.string(), "-vf",
                                       "select=gte(n\\," + std::to_string(std::max(first, 0)) + ")"});
  }
  arguments.insert(arguments.end(), {"-vsync", "0"});
  if (count >= 0) arguments.insert(arguments.end(), {"-frames:v", std::to_string(count)});
  arguments.insert(arguments.end(), {"-f", "rawvideo", "-pix_fmt", "gray16le", "-"});
  ChildProcess child(ffmpeg, arguments);
  const auto pixels = static_cast<std::size_t>(info.width) * static_cast<std::size_t>(info.height);
  std::vector<uint16_t> buffer(pixels);
  std::vector<Image> frames;
  while (count < 0 || static_cast<int>(frames.size()) < count) {
    const std::size_t got = child.read(reinterpret_cast<unsigned char*>(buffer.data()), pixels * 2);
    if (got < pixels * 2) break;
    Image frame = Image::gray(info.width, info.height);
    for (std::size_t i = 0; i < pixels; ++i) frame.values[i] = static_cast<float>(buffer[i] / 65535.0);
    frames.push_back(std::move(frame));
  }
  const int status = child.wait();
  if (status != 0) throw Error(path.string() + ": decoding failed (ffmpeg: " + child.errors() + ")");
  if (frames.empty())
    throw Error(path.string() + ": no frames from frame " + std::to_string(first) + " on (the video has " +
                std::to_string(info.frameCount) + ")");
  return frames;
}

void writeVideo(const fs::path& path, const std::vector<Image>& frames, double frameRate) {
  if (frames.empty()) throw Error(path.string() + ": no frames to write");
  if (!(frameRate > 0 && frameRate <= 1000))
    throw Error(path.string() + ": the frame rate must be above 0 and at most 1000, got " + std::to_string(frameRate));
  const fs::path ffmpeg = requireFfmpeg(path.string());
  const int width = frames[0].width, height = frames[0].height;
  for (const Image& f : frames)
    if (f.width != width || f.height != height || f.channels != 1)
      throw Error(path.string() + ": every video frame must be gray and " + std::to_string(width) + "x" +
                  std::to_string(height));
  fs::path temporary = path;
  temporary += ".tmp.mp4";
  const io::InFlightTemporary inFlight(temporary);
  // H.264 in yuv420p needs even sizes: pad by one black row/column when odd.
  ChildProcess child(ffmpeg, {"-v", "error", "-nostdin", "-y", "-f", "rawvideo", "-pix_fmt", "gray", "-s",
                              std::to_string(width) + "x" + std::to_string(height), "-r", std::to_string(frameRate),
                              "-i", "-", "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-c:v", "libx264", "-pix_fmt",
                              "yuv420p", "-movflags", "+faststart", temporary.string()});
  std::vector<unsigned char> bytes(static_cast<std::size_t>(width * height));
  bool written = true;
  for (const Image& f : frames) {
    for (std::size_t i = 0; i < bytes.size(); ++i)
      bytes[i] = static_cast<unsigned char>(std::lround(std::clamp(f.values[i], 0.0f, 1.0f) * 255.0f));
    if (!(written = child.write(bytes.data(), bytes.size()))) break;
  }
  const int status = child.wait();
  if (!written || status != 0) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw Error(path.string() + ": encoding failed (ffmpeg: " + child.errors() + ")");
  }
  std::error_code error;
  fs::rename(temporary, path, error);
  if (error) throw Error(path.string() + ": cannot rename the written file into place: " + error.message());
}

std::vector<Image> readFrames(const fs::path& path, int first, int count) {
  if (!fs::exists(path)) throw Error(path.string() + ": no such file or folder (expected PNG frames or a video)");
  if (!fs::is_directory(path)) return readVideoFrames(path, first, count);
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(path)) {
    std::string extension = entry.path().extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(), ::tolower);
    if (entry.is_regular_file() && extension == ".png") files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  if (files.empty()) throw Error(path.string() + ": folder holds no .png frames");
  std::vector<Image> frames;
  for (std::size_t i = static_cast<std::size_t>(std::max(first, 0));
       i < files.size() && (count < 0 || static_cast<int>(frames.size()) < count); ++i)
    frames.push_back(readPng(files[i]));
  if (frames.empty()) throw Error(path.string() + ": no frames from frame " + std::to_string(first) + " on");
  return frames;
}

}  // namespace smokesvd::media
