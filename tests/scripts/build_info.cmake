# The build-info header's git commit: the checkout's, or "unknown" outside
# one (cmake/BuildInfo.cmake in script mode; --version and /metrics are
# checked in integration/cli_flags_test.cc).
add_test(NAME build_info.commit_or_unknown
  COMMAND ${CMAKE_COMMAND} -DSOURCE_DIR=${CMAKE_SOURCE_DIR} -DWORK_DIR=${CMAKE_CURRENT_BINARY_DIR}/build_info
    -P ${CMAKE_CURRENT_SOURCE_DIR}/cmake/build_info_check.cmake)
set_tests_properties(build_info.commit_or_unknown PROPERTIES TIMEOUT 60)
