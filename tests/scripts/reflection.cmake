# Python's grpcio, knowing nothing of our .proto files, uses server reflection
# and the health service of a real armature-server.
add_test(NAME python.reflection_and_health
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/reference/reflection_client.py $<TARGET_FILE:armature-server>)
set_tests_properties(python.reflection_and_health PROPERTIES TIMEOUT 120 SKIP_REGULAR_EXPRESSION "SKIP:")
