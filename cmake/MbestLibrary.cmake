# mbest_package_library(<target> <name>): makes <target> the package's mbest::<name>, for a
# project that adds this tree as a subdirectory and for one that finds the installed
# package alike, its headers being the calling folder's include/.
function(mbest_package_library target name)
  add_library(mbest::${name} ALIAS ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${name})
  target_include_directories(${target} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include> $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  install(DIRECTORY include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endfunction()
