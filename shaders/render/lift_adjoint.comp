#version 450
#extension GL_GOOGLE_include_directive : require
// lift_adjoint.glsl with float atomics of VK_EXT_shader_atomic_float.
#define NATIVE_FLOAT_ATOMICS
#include "lift_adjoint.glsl"
