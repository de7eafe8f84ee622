// map_kernels.cuh compiled by the host compiler: its map_job, which map_device.cpp fills for
// the GPU's launches (one definition of the layout both sides read), and its cell functions,
// which the tests run on the CPU against the library's maps.
#pragma once

#include <cmath>
#include <limits>

#define NPEND_GPU_FUNCTION inline
#define NPEND_GPU_INF (std::numeric_limits<double>::infinity())
#define NPEND_GPU_NAN (std::numeric_limits<double>::quiet_NaN())

#include "map_kernels.cuh"
#include "map_models.cuh"
