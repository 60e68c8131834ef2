# Shared compile settings for every hullmap target.
function(hullmap_defaults target)
  target_compile_features(${target} PUBLIC cxx_std_17)
  set_target_properties(${target} PROPERTIES CXX_EXTENSIONS OFF POSITION_INDEPENDENT_CODE ON)
  target_compile_options(${target} PRIVATE -Wall -Wextra)
endfunction()

# A hullmap library: sources in src/, public headers in include/hullmap/<name>/.
function(hullmap_library name)
  add_library(hullmap_${name} STATIC)
  add_library(hullmap::${name} ALIAS hullmap_${name})
  set_target_properties(hullmap_${name} PROPERTIES EXPORT_NAME ${name})
  target_include_directories(hullmap_${name} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  hullmap_defaults(hullmap_${name})
  set_target_properties(hullmap_${name} PROPERTIES UNITY_BUILD ${HULLMAP_UNITY_BUILD})
  install(TARGETS hullmap_${name} EXPORT hullmapTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
  # detail/: white-box headers for the library's own sources, its tests and benchmarks; no installed
  # header includes them.
  install(DIRECTORY include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} PATTERN detail EXCLUDE)
endfunction()
