# Cross-compiling for 64-bit ARM Linux with Debian's cross compiler (apt-get install
# g++-aarch64-linux-gnu); the programs run on x86-64 under qemu-user (qemu-user-static):
#   cmake -S . -B build-aarch64 -DCMAKE_TOOLCHAIN_FILE=cmake/aarch64-linux-gnu.cmake \
#         -DPLUMETRACE_MODEL_ONLY=ON
#   qemu-aarch64-static -L /usr/aarch64-linux-gnu build-aarch64/model_bits
# (scripts/aarch64.sh does both; docs/reliability.md, "Same bits on every machine")
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
set(CMAKE_FIND_ROOT_PATH /usr/aarch64-linux-gnu)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
# why: the tests run the programs under qemu-user, which finds the ARM C library there
set(CMAKE_CROSSCOMPILING_EMULATOR qemu-aarch64-static -L /usr/aarch64-linux-gnu)
# why: GCC notes on aarch64 at each function taking a pair of doubles that C++17 changed how it is
# passed (GCC 10.1); nothing to act on
set(CMAKE_CXX_FLAGS_INIT "-Wno-psabi")
