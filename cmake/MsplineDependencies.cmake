# All dependencies come from Debian packages (scripts/install-deps installs them).

find_package(Eigen3 3.3 REQUIRED NO_MODULE)
find_package(OpenMesh REQUIRED)
find_package(CLI11 REQUIRED)
find_package(nlohmann_json 3 REQUIRED)
# Closest points on triangle meshes (fit errors, error maps): a k-d tree.
find_package(nanoflann REQUIRED)
# Parallel loops over samples (projection, evaluation).
find_package(TBB REQUIRED)
include(OpenSubdiv)

include(Cholmod)
include(Glpk)
