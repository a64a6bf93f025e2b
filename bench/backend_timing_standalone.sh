#!/bin/bash
# Builds bench/backend_timing from the sources alone (no catkin, ROS, OpenCV or PCL), for a GPU machine
# that has a C++17 compiler, CMake and an OpenCL library but not vocal's dependencies:
#   EIGEN=DIR CL_INCLUDE=DIR CL_LIBRARY_DIR=DIR bench/backend_timing_standalone.sh [OUTPUT]
# EIGEN: the folder holding Eigen/ (default /usr/include/eigen3); CL_INCLUDE: the folder holding CL/
# (default /usr/include); CL_LIBRARY_DIR: where libOpenCL.so is, if not on the linker's path.
# Where /etc/OpenCL/vendors names no GPU driver (the backend then takes the first CPU device, and says
# which in its lines), give the loader an ICD file: echo /path/libnvidia-opencl.so > /tmp/nvidia.icd;
# OCL_ICD_VENDORS=/tmp/nvidia.icd backend_timing.
set -euo pipefail
cd "$(dirname "$0")/.."
output=${1:-backend_timing}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake -DINPUT=cl_kernels/odometry.cl -DOUTPUT="$work/odometry_kernels.cpp" -DNAME=kOdometryKernelSource -P cmake/embed_text.cmake
sources="src/core/pinhole_camera.cpp src/core/rgbd_frame.cpp src/core/se3.cpp
  src/odometry/cpu_backend.cpp src/odometry/fast_cpu_backend.cpp src/odometry/soa_frame_pyramid.cpp
  src/odometry/frame_pyramid.cpp src/odometry/normal_equations.cpp src/odometry/odometry_config.cpp
  src/odometry/odometry_backend.cpp src/odometry/opencl_backend.cpp src/odometry/opencl_context.cpp
  src/odometry/tracking_row_avx2.cpp src/odometry/tracking_row_portable.cpp
  src/simulation/synthetic_scene.cpp src/simulation/procedural_texture.cpp src/simulation/rgbd_sensor_model.cpp
  src/simulation/synthetic_trajectory.cpp $work/odometry_kernels.cpp bench/backend_timing.cpp"
library_dir=()
if [ -n "${CL_LIBRARY_DIR:-}" ]; then library_dir=(-L"$CL_LIBRARY_DIR" -Wl,-rpath,"$CL_LIBRARY_DIR"); fi
# shellcheck disable=SC2086
g++ -O2 -std=c++17 -fopenmp -DNDEBUG -DVOCAL_HAVE_OPENCL -Iinclude -I"${EIGEN:-/usr/include/eigen3}" \
  -I"${CL_INCLUDE:-/usr/include}" $sources -o "$output" "${library_dir[@]}" -lOpenCL
echo "built $output"
