# The algorithm libraries (no DDS) installed for other CMake projects: `find_package(scanbus)`,
# then link scanbus::room_measurement_core and the others (examples/measure_room does).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(SCANBUS_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/scanbus)

# Makes `target` installable and exported as scanbus::<target> (the same name as an alias in
# this tree), with its public headers under `include_dir`: all of them, or only HEADERS (paths
# relative to it) where the folder also holds headers of libraries that are not installed.
function(scanbus_export_library target include_dir)
  cmake_parse_arguments(arg "" "" "HEADERS" ${ARGN})
  add_library(scanbus::${target} ALIAS ${target})
  get_filename_component(dir ${include_dir} ABSOLUTE)
  target_include_directories(${target} PUBLIC $<BUILD_INTERFACE:${dir}> $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  install(TARGETS ${target} EXPORT scanbus-targets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
  if(arg_HEADERS)
    foreach(header ${arg_HEADERS})
      get_filename_component(folder ${header} DIRECTORY)
      install(FILES ${dir}/${header} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/${folder})
    endforeach()
  else()
    install(DIRECTORY ${dir}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  endif()
endfunction()

# Once every library is exported: the targets file and the package's config and version.
function(scanbus_install_package)
  install(EXPORT scanbus-targets NAMESPACE scanbus:: DESTINATION ${SCANBUS_CMAKE_DIR})
  configure_package_config_file(${CMAKE_SOURCE_DIR}/cmake/scanbus-config.cmake.in
    ${CMAKE_BINARY_DIR}/scanbus-config.cmake INSTALL_DESTINATION ${SCANBUS_CMAKE_DIR})
  write_basic_package_version_file(${CMAKE_BINARY_DIR}/scanbus-config-version.cmake COMPATIBILITY SameMinorVersion)
  install(FILES ${CMAKE_BINARY_DIR}/scanbus-config.cmake ${CMAKE_BINARY_DIR}/scanbus-config-version.cmake
          DESTINATION ${SCANBUS_CMAKE_DIR})
endfunction()
