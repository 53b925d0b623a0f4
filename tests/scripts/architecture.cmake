# ARCHITECTURE.md's include rules (engine order, server layers, slices never
# including each other, client apart from the server, no folder cycles),
# checked over every source and header by tests/architecture/check_includes.py.
add_test(NAME architecture.include_rules
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/architecture/check_includes.py ${CMAKE_SOURCE_DIR})
set_tests_properties(architecture.include_rules PROPERTIES TIMEOUT 60)
