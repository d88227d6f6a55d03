# Run by the test Install.AProgramOfItsOwnBuildsAgainstThePackage: installs the build tree
# into a scratch prefix, builds examples/consumer against it as a user's project would
# (find_package(mbest), mbest::core, mbest::synth, mbest::validate) and runs it.
# Variables: BUILD_DIR, SOURCE_DIR (the consumer), WORK_DIR (scratch), CXX (compiler).
file(REMOVE_RECURSE "${WORK_DIR}")

function(step what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what} failed (${rc}):\n${out}\n${err}")
  endif()
  set(step_output "${out}" PARENT_SCOPE)
endfunction()

step("cmake --install" ${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${WORK_DIR}/prefix")
step("configuring the consumer against the installed package"
  ${CMAKE_COMMAND} -S "${SOURCE_DIR}" -B "${WORK_DIR}/build" -DCMAKE_BUILD_TYPE=Release
  -DCMAKE_CXX_COMPILER=${CXX} -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix)
step("building the consumer" ${CMAKE_COMMAND} --build "${WORK_DIR}/build")
foreach(scene "s1;1" "s2;1")
  step("running the consumer" "${WORK_DIR}/build/mbest_consumer" ${scene})
  message(STATUS "${step_output}")
  # As many DLOs as rods, and the labels right to within 5 % (the matched DICE).
  if(NOT step_output MATCHES "([0-9]+) rods, ([0-9]+) DLOs detected, strict DICE ([0-9.]+)")
    message(FATAL_ERROR "unexpected output: ${step_output}")
  endif()
  if(NOT CMAKE_MATCH_1 EQUAL CMAKE_MATCH_2 OR CMAKE_MATCH_3 LESS 0.95)
    message(FATAL_ERROR "the consumer detected wrongly: ${step_output}")
  endif()
endforeach()
