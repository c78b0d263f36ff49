#version 450
#extension GL_GOOGLE_include_directive : require
// march_adjoint.glsl with compare-and-swap loops, for devices without float atomics.
#include "march_adjoint.glsl"
