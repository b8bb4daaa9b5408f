#!/usr/bin/env bash
# The one-command GPU check: on a machine with an NVIDIA, AMD or Intel GPU, builds the
# course, runs every chapter's image checks on the GPU's EGL device, measures the speed
# figures that matter there, and writes build/gpu-check/report.md, in ten minutes.
#
#   tools/gpu_check.sh [--gpu N] [--repeat R] [--update-book]
#
#   --gpu N        the EGL device to check (default: the first that works, GPUs first;
#                  the report lists every device)
#   --repeat R     timed runs of each figure, median reported (default 3)
#   --update-book  write the device's row into book/docs/benchmarks.md
#
# It is ./course gpu-check (tools/course_tools/cli/gpu_check.py), which sets up the test
# layer first as ./course test does. Rehearsed on llvmpipe (book/docs/benchmarks.md).
set -euo pipefail
exec "$(cd "$(dirname "$0")/.." && pwd)/course" gpu-check "$@"
