# The browser viewer in headless Chromium (Debian's chromium, driven by
# playwright-core from web/node_modules), and /openapi.json validated as
# OpenAPI 3 by @apidevtools/swagger-parser. The viewer tests skip only when
# /usr/bin/chromium is absent; their screenshots land in build/web-e2e:
# viewer_e2e (clip playback, IK drag), mesh_e2e (skinned mesh, LBS/DQS),
# deform_e2e (dragging a vertex), session_e2e (both drags' WebSocket sessions
# timed against gRPC), blend_e2e (the blend panel on RobotExpressive
# from ../shared/data; it skips without it), character_e2e (RobotExpressive's
# 19 meshes skinned together while Running plays; skips without it), drop_e2e
# (files dropped on the page are imported), retarget_e2e (CMU 01_01 retargeted
# onto RobotExpressive from the Retarget panel and played; skips without them),
# first_look_e2e (header rows on one line at 1200 px, Retarget's first source and its
# answer cleared by another character; the demo assets alone), docs_e2e (the API
# reference at /docs, swagger-ui over /openapi.json, served without a CDN), joint_tree_e2e
# (the joint list, the joint under the pointer highlighted), blend_body_e2e (the blend
# drawn on the demo character's mesh), mixamo_e2e (RobotExpressive under a 0.01-scaled
# Armature in centimetres, web/test/support/mixamo_rig.mjs: the views sized from posed positions;
# skips without it), material_e2e (CesiumMan drawn with its JPEG texture, checked by pixel
# colour; skips without it), crowd_e2e (crowd.html: 1,000 RobotExpressive characters in one CrowdSession
# over its WebSocket, drawn instanced, the HUD's tick figures; skips without it).
set(ARMATURE_VIEWER_TESTS viewer_e2e mesh_e2e deform_e2e blend_e2e character_e2e drop_e2e retarget_e2e first_look_e2e
    docs_e2e joint_tree_e2e blend_body_e2e mixamo_e2e material_e2e crowd_e2e)
if(ARMATURE_NODE AND ARMATURE_WEB_BUILT)
  foreach(test ${ARMATURE_VIEWER_TESTS})
    string(REGEX REPLACE "_e2e$" "" shot ${test})
    add_test(NAME web.${test}
      COMMAND ${ARMATURE_NODE} ${CMAKE_SOURCE_DIR}/web/test/e2e/${test}.mjs
        $<TARGET_FILE:armature-server> ${ARMATURE_WEB_OUT} ${CMAKE_BINARY_DIR}/web-e2e/${shot}.png)
    set_tests_properties(web.${test} PROPERTIES TIMEOUT 180 SKIP_REGULAR_EXPRESSION "SKIP:"
      ENVIRONMENT ARMATURE_SHARED_DATA=${ARMATURE_SHARED_DATA})
  endforeach()
  # The viewer's IK and vertex drags over WebSocket sessions, each step's round
  # trip logged beside the same requests replayed over gRPC (tests/tools/session_replay).
  add_test(NAME web.session_e2e
    COMMAND ${ARMATURE_NODE} ${CMAKE_SOURCE_DIR}/web/test/e2e/session_e2e.mjs
      $<TARGET_FILE:armature-server> ${ARMATURE_WEB_OUT} ${CMAKE_BINARY_DIR}/web-e2e/session.png
      $<TARGET_FILE:session_replay>)
  set_tests_properties(web.session_e2e PROPERTIES TIMEOUT 180 SKIP_REGULAR_EXPRESSION "SKIP:")
  add_test(NAME web.openapi_valid
    COMMAND ${ARMATURE_NODE} ${CMAKE_SOURCE_DIR}/web/test/unit/openapi_validate.mjs $<TARGET_FILE:armature-server>)
  set_tests_properties(web.openapi_valid PROPERTIES TIMEOUT 120)
  # The blend panel's pure parts (upper-body joint, crossfade ramp, motion JSON) in node.
  add_test(NAME web.blend_motion COMMAND ${ARMATURE_NODE} ${CMAKE_SOURCE_DIR}/web/test/unit/blend_motion_test.mjs)
  set_tests_properties(web.blend_motion PROPERTIES TIMEOUT 60)
  # LatestWins (one call in flight, the newest waiting value next) in node.
  add_test(NAME web.latest_wins COMMAND ${ARMATURE_NODE} ${CMAKE_SOURCE_DIR}/web/test/unit/latest_wins_test.mjs)
  set_tests_properties(web.latest_wins PROPERTIES TIMEOUT 60)
  # The Retarget panel's first choice of source clip in node.
  add_test(NAME web.retarget_source COMMAND ${ARMATURE_NODE} ${CMAKE_SOURCE_DIR}/web/test/unit/retarget_source_test.mjs)
  set_tests_properties(web.retarget_source PROPERTIES TIMEOUT 60)
  # A crowd's poses between frames (interpolation, forward kinematics) against three.js, in node.
  add_test(NAME web.crowd_poses COMMAND ${ARMATURE_NODE} ${CMAKE_SOURCE_DIR}/web/test/unit/crowd_poses_test.mjs)
  set_tests_properties(web.crowd_poses PROPERTIES TIMEOUT 60)
else()
  # Not a skip: the setup provides node and web/node_modules.
  foreach(test ${ARMATURE_VIEWER_TESTS} session_e2e openapi_valid blend_motion latest_wins retarget_source crowd_poses)
    add_test(NAME web.${test} COMMAND sh -c
      "echo 'FAIL: node or web/node_modules missing: run scripts/setup.sh test, then configure again'; exit 1")
  endforeach()
endif()
