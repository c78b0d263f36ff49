#include "pipeline/resim/edits.h"

#include "nets/op_registry.h"
#include "runtime/error.h"

namespace smokesvd::resim {
namespace {

int frameNumber(const std::string& text, const std::string& what) {
  std::size_t used = 0;
  int value = -1;
  try {
    value = std::stoi(text, &used);
  } catch (const std::logic_error&) {
    used = 0;
  }
  if (used != text.size() || value < 0) throw Error(what + ": expected a frame number >= 0, got '" + text + "'");
  return value;
}

// "A", "A:" or "A:B" after the '@'.
sim::FrameRange parseFrames(const std::string& text, const std::string& what) {
  sim::FrameRange range;
  const auto colon = text.find(':');
  range.first = frameNumber(text.substr(0, colon), what);
  if (colon != std::string::npos && colon + 1 < text.size()) {
    range.last = frameNumber(text.substr(colon + 1), what);
    if (range.last <= range.first) throw Error(what + ": in @A:B, B must be greater than A (got '" + text + "')");
  }
  return range;
}

// Splits "BODY@FRAMES" at the last '@'.
std::pair<std::string, sim::FrameRange> splitFrames(const std::string& text, const std::string& what) {
  const auto at = text.rfind('@');
  if (at == std::string::npos) return {text, {}};
  return {text.substr(0, at), parseFrames(text.substr(at + 1), what)};
}

}  // namespace

ObstacleEdit parseObstacle(const std::string& text) {
  const std::string what = "--obstacle " + text;
  ObstacleEdit edit;
  edit.text = text;
  const auto [body, frames] = splitFrames(text, what);
  edit.frames = frames;
  const std::string prefix = "sphere:";
  if (body.rfind(prefix, 0) != 0) throw Error(what + ": expected sphere:X,Y,Z,R[@FRAME] (the only obstacle shape)");
  const std::vector<double> v = parseNumberList(body.substr(prefix.size()), what);
  if (v.size() != 4) throw Error(what + ": expected four numbers X,Y,Z,R after 'sphere:'");
  edit.centre = {v[0], v[1], v[2]};
  edit.radius = v[3];
  if (!(edit.radius > 0)) throw Error(what + ": the radius must be > 0");
  return edit;
}

ForceEdit parseForce(const std::string& text) {
  const std::string what = "--force " + text;
  ForceEdit edit;
  edit.text = text;
  const auto [body, frames] = splitFrames(text, what);
  edit.frames = frames;
  const std::string prefix = "uniform:";
  if (body.rfind(prefix, 0) == 0) {
    const std::vector<double> v = parseNumberList(body.substr(prefix.size()), what);
    if (v.size() != 3) throw Error(what + ": expected three numbers AX,AY,AZ after 'uniform:'");
    edit.uniform = true;
    edit.acceleration = {v[0], v[1], v[2]};
    return edit;
  }
  if (body.empty()) throw Error(what + ": expected uniform:AX,AY,AZ or a force field file");
  edit.file = body;
  const auto extension = edit.file.extension();
  if (extension != ".npy" && extension != ".npz")
    throw Error(what + ": expected uniform:AX,AY,AZ or an .npy/.npz force field [z, y, x, 3]");
  return edit;
}

}  // namespace smokesvd::resim
