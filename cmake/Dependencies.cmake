# All third-party packages, found once. The order and the fix-ups follow
# ../shared/STACK.md; each step names the pitfall it avoids.

find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(TIFF REQUIRED)
# Real terrain models (GeoTIFF, PDS3/PDS4, ISIS3) and GeoTIFF map layers.
find_package(GDAL 3.6 CONFIG REQUIRED)
# The evaluations' second ray caster (truth independent of the scanner's).
find_package(embree 3 CONFIG REQUIRED)
find_package(nlohmann_json 3.10 REQUIRED)
find_package(tsl-robin-map 1.2 REQUIRED)
find_package(CLI11 REQUIRED)
find_package(Threads REQUIRED)
find_package(OpenSSL 3 REQUIRED COMPONENTS Crypto)
find_package(SQLite3 REQUIRED)
find_package(CycloneDDS 0.10 REQUIRED)
find_package(OpenMP REQUIRED COMPONENTS CXX)
# NumPy archives (.npz) are zips: minizip reads them (backend/io/Npz.cpp).
find_package(PkgConfig REQUIRED)
pkg_check_modules(MINIZIP REQUIRED IMPORTED_TARGET minizip)
# Image processing for rock sampling (backend/sampling) and reading camera
# images (backend/vision): three core modules only.
find_package(OpenCV 4.6 REQUIRED COMPONENTS core imgproc imgcodecs)

find_package(Qt6 6.4 REQUIRED COMPONENTS Core Gui Widgets OpenGL OpenGLWidgets Concurrent Charts Test)

# VTK's InteractionStyle chain references MPI::MPI_C.
find_package(MPI REQUIRED COMPONENTS C)
# Only modules that do not depend on Qt: Debian's GUISupportQt is built on Qt5.
find_package(VTK 9.1 REQUIRED COMPONENTS
  CommonCore CommonDataModel CommonColor FiltersCore FiltersGeometry FiltersSources
  RenderingCore RenderingOpenGL2 RenderingAnnotation InteractionStyle IOPLY)
# find_package(PCL) overwrites VTK_LIBRARIES, so keep our own list.
set(AMBLER_VTK_LIBRARIES ${VTK_LIBRARIES})

find_package(PCL 1.13 REQUIRED COMPONENTS common io kdtree search features filters registration)
# PCLConfig attaches VTK targets (GUISupportQt among them, built on Qt5) to
# the imported pcl_* targets; strip them so no Qt5 enters our link lines.
foreach(pcl_target IN ITEMS pcl_common pcl_io pcl_io_ply pcl_octree pcl_surface pcl_2d
                            pcl_kdtree pcl_search pcl_features pcl_filters pcl_registration
                            pcl_sample_consensus pcl_visualization)
  if(TARGET ${pcl_target})
    get_target_property(pcl_links ${pcl_target} INTERFACE_LINK_LIBRARIES)
    if(pcl_links)
      list(FILTER pcl_links EXCLUDE REGEX "^VTK::")
      set_target_properties(${pcl_target} PROPERTIES INTERFACE_LINK_LIBRARIES "${pcl_links}")
    endif()
  endif()
endforeach()

# The rover link (issue 6) is carried by Cyclone DDS; found here so a
# machine without it fails at configure time, not later.
find_package(CycloneDDS 0.10 REQUIRED)

find_package(GTest REQUIRED)
find_package(benchmark REQUIRED)
