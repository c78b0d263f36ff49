#!/usr/bin/env bash
# Builds what tools/gpu/check.sh runs on a GPU machine that has a driver but none of this project's
# build dependencies (docs/benchmarks.md, "Checking on a GPU"): build-gpu/bundle.tar.xz (about 13 MiB),
# one file to copy there beside the checkout, holding bundle/ with the stripped smokesvd and test
# programs (built without the optional OpenCV and OpenVDB, whose libraries are most of a bundle's
# size), the shared libraries they load beyond the C and C++ runtimes, and the Debian packages of the
# Vulkan loader and the Khronos validation layer, which check.sh unpacks there.
# Run from anywhere on a machine set up by tools/install-deps.sh; prints the archive's size.
set -euo pipefail
cd "$(dirname "$0")/../.."
if ! command -v xz >/dev/null; then
  echo "make-bundle.sh: xz is missing, which packs the bundle: apt-get install xz-utils" >&2
  exit 2
fi

cmake -S . -B build-gpu -G Ninja -DSMOKESVD_OPENCV=OFF -DSMOKESVD_OPENVDB=OFF
cmake --build build-gpu

bundle=build-gpu/bundle
rm -rf "$bundle"
mkdir -p "$bundle/lib" "$bundle/debs"
strip -o "$bundle/smokesvd" build-gpu/smokesvd
for program in build-gpu/tests/test_*; do
  if [[ -f "$program" && -x "$program" ]]; then strip -o "$bundle/$(basename "$program")" "$program"; fi
done

# Libraries the programs load, less the C/C++ runtime (newer on the GPU machine) and Vulkan's loader
# (its package travels instead, with the validation layer built for it).
for program in "$bundle"/smokesvd "$bundle"/test_*; do
  ldd "$program" | awk '/=> \// {print $3}'
done | sort -u | grep -v -E '/lib(c|m|dl|pthread|rt|stdc\+\+|gcc_s|vulkan)\.so' | xargs -r cp -L -t "$bundle/lib"

(cd "$bundle/debs" && apt-get download libvulkan1 vulkan-validationlayers)
tar -cJf build-gpu/bundle.tar.xz.tmp -C build-gpu bundle
mv build-gpu/bundle.tar.xz.tmp build-gpu/bundle.tar.xz
du -h build-gpu/bundle.tar.xz
