# ARCHITECTURE.md's include rules (engine order, server layers, slices never
# including each other, client apart from the server, no folder cycles),
# checked over every source and header by tests/architecture/check_includes.py.
add_test(NAME architecture.include_rules
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/architecture/check_includes.py ${CMAKE_SOURCE_DIR})
set_tests_properties(architecture.include_rules PROPERTIES TIMEOUT 60)
# ARCHITECTURE.md's size rules (sources a folder, lines a function and a
# file), checked over every source the project writes.
add_test(NAME architecture.shape_rules
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/architecture/check_shape.py ${CMAKE_SOURCE_DIR})
set_tests_properties(architecture.shape_rules PROPERTIES TIMEOUT 60)
# The C++ sources as .clang-format has them (clang-format-14, scripts/test-packages.txt).
add_test(NAME architecture.format
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/architecture/check_format.py ${CMAKE_SOURCE_DIR} clang-format-14)
set_tests_properties(architecture.format PROPERTIES TIMEOUT 120)
