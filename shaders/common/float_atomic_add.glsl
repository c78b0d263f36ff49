// float_atomic_add(BUFFER, INDEX, VALUE): BUFFER[INDEX] += VALUE as one atomic operation, on a storage
// buffer whose elements are declared `float_atomic_t`. Include it before any declaration.
//  - NATIVE_FLOAT_ATOMICS defined: atomicAdd on float (VK_EXT_shader_atomic_float);
//  - otherwise a compare-and-swap loop on the float's bits, which every Vulkan device runs:
//      old = buf[i]; while ((seen = atomicCompSwap(buf[i], old, bits(float(old) + value))) != old) old = seen;
// Both give the same sum up to the order of the additions.
#ifdef NATIVE_FLOAT_ATOMICS
#extension GL_EXT_shader_atomic_float : require
#define float_atomic_t float
#define float_atomic_add(BUFFER, INDEX, VALUE) atomicAdd(BUFFER[INDEX], VALUE)
#else
#define float_atomic_t uint
#define float_atomic_add(BUFFER, INDEX, VALUE)                                                        \
  {                                                                                                 \
    const uint index_ = uint(INDEX);                                                                \
    const float value_ = (VALUE);                                                                   \
    uint expected_ = BUFFER[index_];                                                                \
    for (;;) {                                                                                      \
      const uint seen_ =                                                                            \
          atomicCompSwap(BUFFER[index_], expected_, floatBitsToUint(uintBitsToFloat(expected_) + value_)); \
      if (seen_ == expected_) break;                                                                \
      expected_ = seen_;                                                                            \
    }                                                                                               \
  }
#endif
