# The browser viewer in headless Chromium (Debian's chromium, driven by
# playwright-core from web/node_modules), and /openapi.json validated as
# OpenAPI 3 by @apidevtools/swagger-parser. The viewer test skips only when
# /usr/bin/chromium is absent; its screenshot lands in the build dir.
if(ARMATURE_NODE AND ARMATURE_WEB_BUILT)
  add_test(NAME web.viewer_e2e
    COMMAND ${ARMATURE_NODE} ${CMAKE_SOURCE_DIR}/web/test/viewer_e2e.mjs
      $<TARGET_FILE:armature-server> ${ARMATURE_WEB_OUT} ${CMAKE_BINARY_DIR}/web-e2e/viewer.png)
  set_tests_properties(web.viewer_e2e PROPERTIES TIMEOUT 180 SKIP_REGULAR_EXPRESSION "SKIP:")
  add_test(NAME web.openapi_valid
    COMMAND ${ARMATURE_NODE} ${CMAKE_SOURCE_DIR}/web/test/openapi_validate.mjs $<TARGET_FILE:armature-server>)
  set_tests_properties(web.openapi_valid PROPERTIES TIMEOUT 120)
else()
  # Not a skip: the setup provides node and web/node_modules.
  foreach(name web.viewer_e2e web.openapi_valid)
    add_test(NAME ${name} COMMAND sh -c
      "echo 'FAIL: node or web/node_modules missing: run scripts/setup.sh test, then configure again'; exit 1")
  endforeach()
endif()
