# Every third-party package semfuse builds against. All come from Debian 12 packages;
# deploy/install-deps.sh installs them.
include_guard(GLOBAL)

find_package(CycloneDDS 0.10 REQUIRED)
find_package(Eigen3 3.3 REQUIRED NO_MODULE)
find_package(SemfuseOpenCV REQUIRED)
find_package(spdlog REQUIRED)
find_package(CLI11 REQUIRED)
find_package(yaml-cpp REQUIRED)
find_package(Threads REQUIRED)
find_package(JPEG REQUIRED)  # libjpeg-turbo: colour frames decode straight to RGB (common/wire)
find_package(TBB REQUIRED)

if(SEMFUSE_BUILD_SERVER)
  # Debian installs OpenVDB's find module outside CMake's default module path.
  list(APPEND CMAKE_MODULE_PATH /usr/lib/x86_64-linux-gnu/cmake/OpenVDB)
  find_package(OpenVDB REQUIRED)
endif()
if(SEMFUSE_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()
