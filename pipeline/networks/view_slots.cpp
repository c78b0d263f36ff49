#include "pipeline/networks/view_slots.h"

namespace smokesvd::networks {

double slotAngle(int slot) { return 180.0 * slot / kSlots; }

GridSize presetGrid(const Preset& p) { return p.grid; }

std::vector<Camera> slotCameras(const Preset& p) {
  return orbitCameras(orbitAngles(kSlots), presetGrid(p), p.imageWidth, p.imageHeight);
}

Camera orbitCameraAt(const Preset& p, double angleDegrees) {
  return orbitCamera(angleDegrees, presetGrid(p), p.imageWidth, p.imageHeight);
}

const std::vector<int>& nearSlots() {
  static const std::vector<int> slots{1, 7, 9, 15};
  return slots;
}
const std::vector<int>& midSlots() {
  static const std::vector<int> slots{2, 6, 10, 14};
  return slots;
}
const std::vector<int>& farSlots() {
  static const std::vector<int> slots{3, 4, 5, 11, 12, 13};
  return slots;
}

}  // namespace smokesvd::networks
