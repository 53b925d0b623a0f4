# The TypeScript client (clients/typescript, @armature/client): its stubs
# generated from proto/ by protoc-gen-es and the package compiled with tsc (the
# fixture), then its test against a real armature-server: gRPC-Web through the
# client equals gRPC. scripts/setup.sh test installs its node_modules (npm ci
# from the committed package-lock.json).
set(TS_CLIENT_DIR ${CMAKE_SOURCE_DIR}/clients/typescript)
find_program(ARMATURE_PROTOC NAMES protoc)
if(ARMATURE_NODE AND ARMATURE_PROTOC AND EXISTS ${TS_CLIENT_DIR}/node_modules/typescript)
  add_test(NAME typescript_client.build
    COMMAND ${CMAKE_COMMAND} -E env PROTOC=${ARMATURE_PROTOC}
      sh -c "'${ARMATURE_NODE}' scripts/generate.mjs && '${ARMATURE_NODE}' node_modules/typescript/bin/tsc -p tsconfig.json"
    WORKING_DIRECTORY ${TS_CLIENT_DIR})
  set_tests_properties(typescript_client.build PROPERTIES
    TIMEOUT 180 FIXTURES_SETUP typescript_client_built RESOURCE_LOCK typescript_client_source)
  add_test(NAME typescript_client.api
    COMMAND ${ARMATURE_NODE} --experimental-websocket --test-reporter=spec ${TS_CLIENT_DIR}/test/client.test.mjs
      $<TARGET_FILE:armature-server>)
  set_tests_properties(typescript_client.api PROPERTIES
    TIMEOUT 180 FIXTURES_REQUIRED typescript_client_built RESOURCE_LOCK typescript_client_source)
  # The crowd session over its WebSocket route, decoded poses against EvaluateClip
  # (CMU 01_01 and RobotExpressive from ../shared/data; it skips without them).
  add_test(NAME typescript_client.crowd
    COMMAND ${ARMATURE_NODE} --experimental-websocket --test-reporter=spec ${TS_CLIENT_DIR}/test/crowd.test.mjs
      $<TARGET_FILE:armature-server>)
  set_tests_properties(typescript_client.crowd PROPERTIES
    TIMEOUT 180 FIXTURES_REQUIRED typescript_client_built RESOURCE_LOCK typescript_client_source
    ENVIRONMENT ARMATURE_SHARED_DATA=${ARMATURE_SHARED_DATA})
else()
  # Not a skip: the setup provides node, protoc and the client's node_modules.
  foreach(test api crowd)
    add_test(NAME typescript_client.${test} COMMAND sh -c
      "echo 'FAIL: node, protoc or clients/typescript/node_modules missing: run scripts/setup.sh test, then configure again'; exit 1")
  endforeach()
endif()
