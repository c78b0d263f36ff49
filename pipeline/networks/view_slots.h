// The 16 view slots of the method: orbit cameras at 11.25 i degrees, i = 0..15, on [0, 180) (slot 0 the
// front view, slot 8 the side view), orthographic, framing the whole volume (pipeline/camera/camera.h),
// at the preset's image size. The refinement groups of Algorithm 2 by their distance to the two input
// views: near (+-11.25 deg: 1, 7, 9, 15), mid (+-22.5 deg: 2, 6, 10, 14) and far (3, 4, 5, 11, 12, 13).
#pragma once

#include <vector>

#include "pipeline/camera/camera.h"
#include "pipeline/preset.h"

namespace smokesvd::networks {

constexpr int kSlots = 16;
constexpr int kFrontSlot = 0;
constexpr int kSideSlot = 8;

double slotAngle(int slot);  // 11.25 slot degrees
GridSize presetGrid(const Preset& preset);
std::vector<Camera> slotCameras(const Preset& preset);
Camera orbitCameraAt(const Preset& preset, double angleDegrees);

const std::vector<int>& nearSlots();
const std::vector<int>& midSlots();
const std::vector<int>& farSlots();

}  // namespace smokesvd::networks
