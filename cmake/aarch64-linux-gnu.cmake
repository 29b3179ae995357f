# Cross build for arm64 with Debian's g++-aarch64-linux-gnu, run under qemu-user
# (tests/arm64/qemu_tests.sh). HEIGHTMARCH_ARM64_SYSROOT holds the arm64 libraries that Debian's
# cross packages lack (TBB and Highway, unpacked from Debian's arm64 packages; GLM's headers).
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)  # GoogleTest, built from source, enables C
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
set(CMAKE_FIND_ROOT_PATH /usr/aarch64-linux-gnu ${HEIGHTMARCH_ARM64_SYSROOT})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
