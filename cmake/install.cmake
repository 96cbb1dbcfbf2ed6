# Install rules and the CMake package: find_package(rayscout CONFIG) gives rayscout::<module>,
# the names the tree's aliases have, so an engine's target_link_libraries reads the same either way.
include(CMakePackageConfigHelpers)

set(rayscout_export_targets rayscout_core_private)  # see src/core/CMakeLists.txt
foreach(module IN LISTS RAYSCOUT_MODULES)
  if(TARGET rayscout_${module})  # embree only with RAYSCOUT_WITH_EMBREE
    set_target_properties(rayscout_${module} PROPERTIES EXPORT_NAME ${module})
    list(APPEND rayscout_export_targets rayscout_${module})
  endif()
endforeach()
set_target_properties(rayscout_core_private PROPERTIES EXPORT_NAME core_private)

# Shared libraries (-DBUILD_SHARED_LIBS=ON): the installed CLI and libraries find rayscout's
# libraries relative to themselves, so the prefix runs without LD_LIBRARY_PATH wherever it is
# moved, and the dependencies outside the system folders where they were linked from.
get_target_property(rayscout_library_type rayscout_core TYPE)
if(rayscout_library_type STREQUAL SHARED_LIBRARY)
  file(RELATIVE_PATH rayscout_bin_to_lib ${CMAKE_INSTALL_FULL_BINDIR} ${CMAKE_INSTALL_FULL_LIBDIR})
  set_target_properties(${rayscout_export_targets} PROPERTIES INSTALL_RPATH "$ORIGIN" INSTALL_RPATH_USE_LINK_PATH ON)
  set_target_properties(rayscout PROPERTIES INSTALL_RPATH "$ORIGIN/${rayscout_bin_to_lib}" INSTALL_RPATH_USE_LINK_PATH ON)
endif()

install(TARGETS ${rayscout_export_targets} EXPORT rayscoutTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS rayscout RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
# The embree module's header only when its library is built.
if(TARGET rayscout_embree)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/rayscout DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
else()
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/rayscout DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} PATTERN embree EXCLUDE)
endif()

set(rayscout_cmake_dir ${CMAKE_INSTALL_LIBDIR}/cmake/rayscout)
install(EXPORT rayscoutTargets NAMESPACE rayscout:: DESTINATION ${rayscout_cmake_dir})
# What the config tells a consumer about this build (plain ON/OFF for its if()s).
foreach(option NATIVE WITH_EMBREE)
  if(RAYSCOUT_${option})
    set(rayscout_config_${option} ON)
  else()
    set(rayscout_config_${option} OFF)
  endif()
endforeach()
configure_package_config_file(cmake/rayscoutConfig.cmake.in ${PROJECT_BINARY_DIR}/rayscoutConfig.cmake
                              INSTALL_DESTINATION ${rayscout_cmake_dir})
# 0.x: a minor release may change the API, so only the same minor version is compatible.
if(PROJECT_VERSION_MAJOR EQUAL 0)
  set(rayscout_compatibility SameMinorVersion)
else()
  set(rayscout_compatibility SameMajorVersion)
endif()
write_basic_package_version_file(${PROJECT_BINARY_DIR}/rayscoutConfigVersion.cmake
                                 COMPATIBILITY ${rayscout_compatibility})
install(FILES ${PROJECT_BINARY_DIR}/rayscoutConfig.cmake ${PROJECT_BINARY_DIR}/rayscoutConfigVersion.cmake
        DESTINATION ${rayscout_cmake_dir})

# rayscout.pc for pkg-config, every module in link order. The packages the libraries link go to
# Requires.private and Libs.private when the libraries are shared; static, to Requires and Libs,
# so that a plain `pkg-config --libs rayscout` links either. TBB is public, as for rayscout::core:
# an engine sets the thread count with tbb::global_control.
set(rayscout_pc_libs)
foreach(module manylight render image accelerators shafts dacrt embree bvh scene core)
  if(TARGET rayscout_${module})
    string(APPEND rayscout_pc_libs " -lrayscout_${module}")
  endif()
endforeach()
string(STRIP "${rayscout_pc_libs}" rayscout_pc_libs)
set(rayscout_pc_requires tbb)
set(rayscout_pc_requires_private "assimp OpenEXR fmt")
set(rayscout_pc_libs_private)
if(TARGET rayscout_embree)
  set(rayscout_pc_libs_private -lembree3)  # Embree 3 has no .pc file
endif()
if(RAYSCOUT_SANITIZE)
  string(APPEND rayscout_pc_libs " -fsanitize=${RAYSCOUT_SANITIZE}")
endif()
if(rayscout_library_type STREQUAL SHARED_LIBRARY)
  set(rayscout_pc_kind shared)
else()
  set(rayscout_pc_kind static)
  string(APPEND rayscout_pc_requires " ${rayscout_pc_requires_private}")
  string(APPEND rayscout_pc_libs " ${rayscout_pc_libs_private}")
  set(rayscout_pc_requires_private)
  set(rayscout_pc_libs_private)
endif()
file(RELATIVE_PATH rayscout_pc_to_prefix ${CMAKE_INSTALL_FULL_LIBDIR}/pkgconfig ${CMAKE_INSTALL_PREFIX})
string(REGEX REPLACE "/$" "" rayscout_pc_to_prefix ${rayscout_pc_to_prefix})  # ../../ -> ../..
file(RELATIVE_PATH rayscout_pc_libdir ${CMAKE_INSTALL_PREFIX} ${CMAKE_INSTALL_FULL_LIBDIR})
file(RELATIVE_PATH rayscout_pc_includedir ${CMAKE_INSTALL_PREFIX} ${CMAKE_INSTALL_FULL_INCLUDEDIR})
configure_file(cmake/rayscout.pc.in ${PROJECT_BINARY_DIR}/rayscout.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/rayscout.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
