# cmake/BuildInfo.cmake run in script mode on three directories: the checkout
# itself (its commit), a folder inside the checkout but not its root (a tarball
# unpacked inside another repository: "unknown", not that repository's
# commit) and a folder outside any repository ("unknown", or the commit
# ARMATURE_GIT_COMMIT names, as the container build does).
#   cmake -DSOURCE_DIR=<repo> -DWORK_DIR=<scratch> -P build_info_check.cmake

function(write_info header dir)  # further arguments: -D definitions
  execute_process(COMMAND ${CMAKE_COMMAND} -DSOURCE_DIR=${dir} -DVERSION=9.8.7 -DHEADER=${header} ${ARGN}
    -P ${SOURCE_DIR}/cmake/BuildInfo.cmake RESULT_VARIABLE rc ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "BuildInfo.cmake failed on ${dir}: ${err}")
  endif()
endfunction()

function(expect_commit header expected_regex what)
  file(READ ${header} text)
  if(NOT text MATCHES "kVersion\\[\\] = \"9\\.8\\.7\"")
    message(FATAL_ERROR "${what}: the version is not 9.8.7 in\n${text}")
  endif()
  if(NOT text MATCHES "kCommit\\[\\] = \"${expected_regex}\"")
    message(FATAL_ERROR "${what}: expected commit \"${expected_regex}\" in\n${text}")
  endif()
  message(STATUS "${what}: ok")
endfunction()

file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR}/nested)

# Outside any repository: a fresh folder under the system's temp dir.
string(RANDOM LENGTH 12 suffix)
set(outside /tmp/armature-build-info-${suffix})
file(MAKE_DIRECTORY ${outside})
write_info(${WORK_DIR}/outside.h ${outside})
expect_commit(${WORK_DIR}/outside.h "unknown" "outside a git repository")
write_info(${WORK_DIR}/told.h ${outside} -DARMATURE_GIT_COMMIT=00c0ffee1234)
expect_commit(${WORK_DIR}/told.h "00c0ffee1234" "outside a repository, told the commit")
write_info(${WORK_DIR}/told_wrong.h ${outside} "-DARMATURE_GIT_COMMIT=main; rm -rf")
expect_commit(${WORK_DIR}/told_wrong.h "unknown" "told a commit that is not one")
file(REMOVE_RECURSE ${outside})

find_package(Git QUIET)
execute_process(COMMAND ${GIT_EXECUTABLE} rev-parse --short=12 HEAD WORKING_DIRECTORY ${SOURCE_DIR}
  OUTPUT_VARIABLE head RESULT_VARIABLE head_rc OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
if(GIT_FOUND AND head_rc EQUAL 0)
  write_info(${WORK_DIR}/nested.h ${WORK_DIR}/nested)
  expect_commit(${WORK_DIR}/nested.h "unknown" "a folder inside a checkout, not its root")
  write_info(${WORK_DIR}/checkout.h ${SOURCE_DIR})
  expect_commit(${WORK_DIR}/checkout.h "${head}" "the checkout")
else()
  message(STATUS "the sources are not a git checkout: only the outside case was checked")
endif()
