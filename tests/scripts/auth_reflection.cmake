# With --auth-token-file, reflection and health stay open and the API needs
# the bearer token (checked with grpcio, a client that is not ours).
add_test(NAME python.auth_reflection_open_api_closed
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/reference/auth_reflection_client.py $<TARGET_FILE:armature-server>)
set_tests_properties(python.auth_reflection_open_api_closed PROPERTIES TIMEOUT 120 SKIP_REGULAR_EXPRESSION "SKIP:")
# Reflection v1 stays open behind a token as v1alpha does.
add_test(NAME python.auth_reflection_v1_open_api_closed
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/reference/auth_reflection_client.py $<TARGET_FILE:armature-server> v1)
set_tests_properties(python.auth_reflection_v1_open_api_closed PROPERTIES TIMEOUT 120 SKIP_REGULAR_EXPRESSION "SKIP:")
