# gRPC-Web through a real client (tests/clients/grpc_web): connect-web's
# gRPC-Web transport with stubs protoc-gen-es generates from proto/ at test
# time, against the same calls over gRPC. scripts/setup.sh test installs its
# node_modules (npm ci from the committed package-lock.json).
set(GRPC_WEB_CLIENT_DIR ${CMAKE_CURRENT_SOURCE_DIR}/clients/grpc_web)
find_program(ARMATURE_PROTOC NAMES protoc)
if(ARMATURE_NODE AND ARMATURE_PROTOC AND EXISTS ${GRPC_WEB_CLIENT_DIR}/node_modules/@connectrpc/connect-web)
  add_test(NAME grpc_web.connect_client
    COMMAND ${ARMATURE_NODE} --test-reporter=spec ${GRPC_WEB_CLIENT_DIR}/grpc_web_client.test.mjs
      $<TARGET_FILE:armature-server> ${ARMATURE_PROTOC} ${CMAKE_SOURCE_DIR}/proto)
  set_tests_properties(grpc_web.connect_client PROPERTIES TIMEOUT 180)
else()
  # Not a skip: the setup provides node, protoc and the client's node_modules.
  add_test(NAME grpc_web.connect_client COMMAND sh -c
    "echo 'FAIL: node, protoc or tests/clients/grpc_web/node_modules missing: run scripts/setup.sh test, then configure again'; exit 1")
endif()
