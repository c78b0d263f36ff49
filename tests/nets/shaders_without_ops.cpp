#include "tests/nets/shaders_without_ops.h"

namespace smokesvd::testing {

const std::vector<ShaderCoveredElsewhere>& shadersWithoutOps() {
  static const std::vector<ShaderCoveredElsewhere> table = {
      // benchmarks and the device's reference figures
      {"bench/fma_peak", "tests/runtime/benchmark_kernels_test.cpp", "BenchmarkKernelsTest.FmaPeakComputesItsChains"},
      {"tensor/copy_storage", "tests/runtime/benchmark_kernels_test.cpp", "BenchmarkKernelsTest.StorageCopyCopiesEveryElement"},
      {"tensor/empty", "tests/runtime/benchmark_kernels_test.cpp", "BenchmarkKernelsTest.EmptyDispatchesLeaveABatchIntact"},
      // evaluation metrics
      {"eval/ssim", "tests/pipeline/eval/image_metrics_test.cpp", "ImageMetricsTest.MseAndSsimOfRandomStacksMatchTheDoubleFormulas"},
      // the optimiser and the diffusion sampler
      {"nn/adam", "tests/nets/optim/adam_test.cpp", "AdamTest.TenStepsMatchDoubleReference"},
      {"nn/optimizer_step", "tests/nets/optim/adam_test.cpp", "AdamTest.TenStepsMatchDoubleReference"},
      {"nn/grad_norm", "tests/nets/optim/optim_test.cpp", "OptimTest.ClippingMatchesDoubleReference"},
      {"nn/clip_factor", "tests/nets/optim/optim_test.cpp", "OptimTest.ClippingMatchesDoubleReference"},
      {"nn/clip_grad", "tests/nets/optim/optim_test.cpp", "OptimTest.ClippingMatchesDoubleReference"},
      {"nn/ema", "tests/nets/optim/optim_test.cpp", "OptimTest.EmaFollowsDoubleReference"},
      {"nn/ddim_step", "tests/nets/diffusion/ddim_test.cpp", "DdimTest.StepKernelMatchesTheFormula"},
      // the GroupNorm merge of several chunks per group: the op examples' groups fit one chunk
      {"nn/group_norm_finalize", "tests/nets/ops/group_norm_test.cpp", "GroupNormTest.ForwardMatchesReference"},
      // the simulator's inflow sources
      {"physics/inflow_density", "tests/pipeline/physics/sources_test.cpp", "SourcesTest.DensityAndTemperatureInflowOfEveryShapeAndMode"},
      {"physics/inflow_velocity", "tests/pipeline/physics/sources_test.cpp", "SourcesTest.VelocityBlendsOverCoveredFaces"},
      // the runtime's NaN/Inf guard
      {"runtime/check_finite", "tests/runtime/finite_check_test.cpp",
       "FiniteCheckTest.NamesTheShaderBindingAndElementOfAPlantedNan"},
      // tensor utilities
      {"tensor/copy", "tests/runtime/elementwise_test.cpp", "ElementwiseTest.CopyAddSubMulDiv"},
      {"tensor/count_items", "tests/runtime/flat_index_test.cpp", "FlatIndexTest.TwoRowDispatchVisitsEveryItemOnce"},
      {"tensor/reduce", "tests/runtime/reduce_test.cpp", "ReduceTest.SumMaxMeanMatchDoubleReference"},
  };
  return table;
}

}  // namespace smokesvd::testing
