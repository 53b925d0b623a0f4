# The Python client (clients/python): pip installs it offline (stubs generated
# at build time by protoc and grpc_python_plugin), then its tests run in that
# install against a real armature-server. The install is the fixture.
set(PYTHON_CLIENT_WORK ${CMAKE_CURRENT_BINARY_DIR}/python_client)
add_test(NAME python_client.install_offline
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/clients/python/install_offline.py
    $<TARGET_FILE:armature-server> ${CMAKE_SOURCE_DIR}/clients/python ${PYTHON_CLIENT_WORK})
set_tests_properties(python_client.install_offline PROPERTIES
  TIMEOUT 300 FIXTURES_SETUP python_client_installed SKIP_REGULAR_EXPRESSION "SKIP:"
  # pip builds in clients/python/build: one install at a time.
  RESOURCE_LOCK python_client_source)
add_test(NAME python_client.api
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/clients/python/test_client.py
    ${PYTHON_CLIENT_WORK}/venv/bin/python $<TARGET_FILE:armature-server> $<TARGET_FILE:armature>)
set_tests_properties(python_client.api PROPERTIES
  TIMEOUT 300 FIXTURES_REQUIRED python_client_installed SKIP_REGULAR_EXPRESSION "SKIP:")
add_test(NAME python_client.crowd
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/clients/python/test_crowd.py
    ${PYTHON_CLIENT_WORK}/venv/bin/python $<TARGET_FILE:armature-server>)
set_tests_properties(python_client.crowd PROPERTIES
  TIMEOUT 300 FIXTURES_REQUIRED python_client_installed SKIP_REGULAR_EXPRESSION "SKIP:")
