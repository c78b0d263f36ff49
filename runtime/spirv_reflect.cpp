#include "runtime/spirv_reflect.h"

#include <algorithm>
#include <functional>
#include <map>
#include <set>
#include <string_view>

#include "runtime/error.h"

namespace smokesvd {
namespace {

// The few SPIR-V opcodes, decorations and storage classes the reflection needs (SPIR-V 1.5 spec).
enum Op : uint32_t {
  OpName = 5, OpTypeInt = 21, OpTypeVector = 23, OpTypeMatrix = 24, OpTypeImage = 25, OpTypeSampledImage = 27,
  OpTypeArray = 28, OpTypeRuntimeArray = 29, OpTypeStruct = 30, OpTypePointer = 32, OpVariable = 59,
  OpDecorate = 71, OpMemberDecorate = 72,
};
enum Decoration : uint32_t { SpecId = 1, Block = 2, BufferBlock = 3, NonWritable = 24, NonReadable = 25,
                             Binding = 33, DescriptorSet = 34 };
enum StorageClass : uint32_t { UniformConstant = 0, Uniform = 2, PushConstant = 9, StorageBuffer = 12 };
constexpr uint32_t kDimBuffer = 5;
constexpr uint32_t kMagic = 0x07230203;

struct Decorations {
  std::set<uint32_t> flags;  // Block, BufferBlock, NonWritable, NonReadable
  std::map<uint32_t, uint32_t> values;  // Binding, DescriptorSet, SpecId -> literal
  std::set<uint32_t> memberFlagsAll;  // a member decoration present on every member seen
  std::map<uint32_t, std::set<uint32_t>> memberFlags;  // member -> flags
};

std::string literalString(std::span<const uint32_t> words) {
  std::string text;
  for (uint32_t word : words) {
    for (int byte = 0; byte < 4; ++byte) {
      const char c = static_cast<char>((word >> (8 * byte)) & 0xff);
      if (c == '\0') return text;
      text += c;
    }
  }
  return text;
}

}  // namespace

ShaderInterface reflectShader(std::span<const uint32_t> spirv, const std::string& shaderName) {
  auto fail = [&](const std::string& why) -> Error { return Error("shader '" + shaderName + "': " + why); };
  if (spirv.size() < 5 || spirv[0] != kMagic) throw fail("not a SPIR-V module");

  std::map<uint32_t, Decorations> decorations;
  std::map<uint32_t, std::string> names;
  std::map<uint32_t, std::vector<uint32_t>> types;  // id -> instruction words, word 0 the opcode
  struct Variable { uint32_t id, pointerType, storageClass; };
  std::vector<Variable> variables;

  for (std::size_t at = 5; at < spirv.size();) {
    const uint32_t count = spirv[at] >> 16;
    const uint32_t opcode = spirv[at] & 0xffff;
    if (count == 0 || at + count > spirv.size()) throw fail("truncated instruction");
    std::span<const uint32_t> words = spirv.subspan(at, count);
    switch (opcode) {
      case OpName: names[words[1]] = literalString(words.subspan(2)); break;
      case OpDecorate: {
        Decorations& d = decorations[words[1]];
        if (count >= 4) d.values[words[2]] = words[3];
        else d.flags.insert(words[2]);
        break;
      }
      case OpMemberDecorate: decorations[words[1]].memberFlags[words[2]].insert(words[3]); break;
      case OpTypeInt: case OpTypeVector: case OpTypeMatrix:
      case OpTypeImage: case OpTypeSampledImage: case OpTypeArray: case OpTypeRuntimeArray:
      case OpTypeStruct: case OpTypePointer:
        types[words[1]].assign(words.begin(), words.end());
        types[words[1]][0] = opcode;  // keep the opcode alone in the first word
        break;
      case OpVariable: variables.push_back({words[2], words[1], words[3]}); break;
      default: break;
    }
    at += count;
  }

  auto hasFlag = [&](uint32_t id, uint32_t flag) {
    auto found = decorations.find(id);
    return found != decorations.end() && found->second.flags.count(flag) > 0;
  };
  auto everyMemberHas = [&](uint32_t structId, uint32_t flag) {
    auto found = decorations.find(structId);
    const std::size_t members = types.count(structId) ? types[structId].size() - 2 : 0;
    if (found == decorations.end() || members == 0) return false;
    for (std::size_t m = 0; m < members; ++m) {
      auto flags = found->second.memberFlags.find(static_cast<uint32_t>(m));
      if (flags == found->second.memberFlags.end() || flags->second.count(flag) == 0) return false;
    }
    return true;
  };

  // Whether a type holds a signed integer anywhere (int, ivec, arrays and structs of them).
  std::function<bool(uint32_t)> holdsSignedInt = [&](uint32_t id) -> bool {
    auto found = types.find(id);
    if (found == types.end()) return false;
    const std::vector<uint32_t>& type = found->second;
    switch (type[0]) {
      case OpTypeInt: return type[3] == 1;
      case OpTypeVector: case OpTypeMatrix: case OpTypeArray: case OpTypeRuntimeArray: return holdsSignedInt(type[2]);
      case OpTypeStruct:
        for (std::size_t m = 2; m < type.size(); ++m)
          if (holdsSignedInt(type[m])) return true;
        return false;
      default: return false;
    }
  };

  ShaderInterface result;
  for (const auto& [id, d] : decorations) {
    auto spec = d.values.find(SpecId);
    if (spec != d.values.end()) result.specializationIds.push_back(spec->second);
  }
  std::sort(result.specializationIds.begin(), result.specializationIds.end());

  for (const Variable& variable : variables) {
    if (variable.storageClass == PushConstant) {
      result.hasPushConstants = true;
      continue;
    }
    auto decoration = decorations.find(variable.id);
    if (decoration == decorations.end() || !decoration->second.values.count(Binding)) continue;
    const uint32_t set = decoration->second.values.count(DescriptorSet) ? decoration->second.values.at(DescriptorSet) : 0;
    BindingInfo info;
    info.binding = decoration->second.values.at(Binding);
    info.name = names.count(variable.id) ? names[variable.id] : "";
    if (set != 0) throw fail("binding '" + info.name + "' uses descriptor set " + std::to_string(set) + "; only set 0");
    const std::vector<uint32_t>& pointer = types.at(variable.pointerType);
    uint32_t pointee = pointer[3];
    const std::vector<uint32_t>* type = &types.at(pointee);
    if ((*type)[0] == OpTypeArray || (*type)[0] == OpTypeRuntimeArray)
      throw fail("binding '" + info.name + "' is an array of descriptors, which smokesvd does not use");
    if ((*type)[0] == OpTypeSampledImage) type = &types.at((*type)[2]);

    if ((*type)[0] == OpTypeImage) {
      if ((*type)[3] != kDimBuffer || (*type)[7] != 1)
        throw fail("binding '" + info.name + "' is an image; only samplerBuffer/textureBuffer texel reads are supported");
      info.kind = BindingKind::UniformTexelBuffer;
      info.reads = true;
      info.writes = false;
    } else if ((*type)[0] == OpTypeStruct &&
               (variable.storageClass == StorageBuffer ||
                (variable.storageClass == Uniform && hasFlag(pointee, BufferBlock)))) {
      if (info.name.empty() && names.count(pointee)) info.name = names[pointee];
      info.kind = BindingKind::StorageBuffer;
      info.writes = !(hasFlag(variable.id, NonWritable) || everyMemberHas(pointee, NonWritable));
      info.reads = !(hasFlag(variable.id, NonReadable) || everyMemberHas(pointee, NonReadable));
      const std::string block = names.count(pointee) ? names[pointee] : "";
      const std::string_view suffix = "NonFinite";
      info.finiteFloats = !holdsSignedInt(pointee) && !block.ends_with(suffix);
    } else {
      throw fail("binding '" + info.name + "' has a kind smokesvd does not bind (use buffer or samplerBuffer)");
    }
    result.bindings.push_back(info);
  }
  std::sort(result.bindings.begin(), result.bindings.end(),
            [](const BindingInfo& a, const BindingInfo& b) { return a.binding < b.binding; });
  for (std::size_t i = 0; i < result.bindings.size(); ++i) {
    if (result.bindings[i].binding != i)
      throw fail("bindings must be numbered 0, 1, 2, ... without gaps; found binding " +
                 std::to_string(result.bindings[i].binding) + " at position " + std::to_string(i));
  }
  return result;
}

}  // namespace smokesvd
