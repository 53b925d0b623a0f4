# Python's grpcio, knowing nothing of our .proto files, uses server reflection
# and the health service of a real armature-server.
add_test(NAME python.reflection_and_health
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/reference/reflection_client.py $<TARGET_FILE:armature-server>)
set_tests_properties(python.reflection_and_health PROPERTIES TIMEOUT 120 SKIP_REGULAR_EXPRESSION "SKIP:")
# The same through reflection v1 (served by server/host/reflection_v1_service),
# which must also list exactly what gRPC's own v1alpha plugin lists.
add_test(NAME python.reflection_v1_and_health
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/reference/reflection_client.py $<TARGET_FILE:armature-server> v1)
set_tests_properties(python.reflection_v1_and_health PROPERTIES TIMEOUT 120 SKIP_REGULAR_EXPRESSION "SKIP:")
