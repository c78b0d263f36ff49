#include "runtime/finite_check.h"

#include "runtime/error.h"

namespace smokesvd {
namespace {

constexpr uint32_t kNone = 0xFFFFFFFFu;

std::string kindName(uint32_t kind) {
  switch (kind) {
    case 1: return "NaN";
    case 2: return "+Inf";
    default: return "-Inf";
  }
}

// [i0, i1, ...] of flat index `flat` in `shape` (last axis fastest).
Shape multiIndex(uint64_t flat, const Shape& shape) {
  Shape index(shape.size());
  for (std::size_t axis = shape.size(); axis-- > 0;) {
    const auto extent = static_cast<uint64_t>(shape[axis]);
    index[axis] = static_cast<int64_t>(flat % extent);
    flat /= extent;
  }
  return index;
}

}  // namespace

FiniteCheck::Slot FiniteCheck::add(const std::string& shader, uint32_t dispatch, const BindingInfo& binding,
                                   uint64_t elements, Shape shape) {
  const std::size_t slot = scans_.size() % kSlotsPerChunk;
  const bool resetChunk = slot == 0;
  if (resetChunk) chunks_.push_back(std::make_unique<Buffer>(context_, kSlotBytes * kSlotsPerChunk, true));
  scans_.push_back({shader, dispatch, binding.binding, binding.name, elements, std::move(shape)});
  return {chunks_.back()->handle(), slot * kSlotBytes, sizeof(uint32_t), resetChunk};
}

Buffer& FiniteCheck::snapshot(std::size_t index, uint64_t bytes) {
  if (snapshotFor_.size() <= index) snapshotFor_.resize(index + 1, nullptr);
  Buffer*& current = snapshotFor_[index];
  if (!current || current->capacity() < bytes) {
    snapshots_.push_back(std::make_unique<Buffer>(context_, BufferPool::sizeClass(bytes)));
    current = snapshots_.back().get();
  }
  return *current;
}

void FiniteCheck::throwIfFound() const {
  for (std::size_t i = 0; i < scans_.size(); ++i) {
    uint32_t report = kNone;
    chunks_[i / kSlotsPerChunk]->read(&report, sizeof report, (i % kSlotsPerChunk) * kSlotBytes);
    if (report == kNone) continue;
    const Scan& scan = scans_[i];
    const uint64_t element = report / 4;
    std::string where = "element " + std::to_string(element) + " of " + std::to_string(scan.elements);
    if (scan.shape.size() > 1) where += ", index " + toString(multiIndex(element, scan.shape)) + " of " + toString(scan.shape);
    throw Error("finite check (SMOKESVD_CHECK): " + kindName(report % 4) + " written by dispatch " +
                std::to_string(scan.dispatch) + ", shader '" + scan.shader + "', binding " +
                std::to_string(scan.binding) + " '" + scan.bindingName + "', at " + where +
                "; every buffer written before it was finite");
  }
}

void FiniteCheck::clear() {
  chunks_.clear();
  scans_.clear();
  snapshots_.clear();
  snapshotFor_.clear();
}

}  // namespace smokesvd
