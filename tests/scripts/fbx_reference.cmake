# FBX import (issue 33): a Mixamo-style FBX (tests/data/fbx/mixamo_walk.fbx)
# through a real server and the CLI: its pose against three.js's FBXLoader,
# retargeted onto RobotExpressive and the demo character, exported as .glb and
# played by three.js's GLTFLoader with the same joint positions, reloaded after
# a restart (tests/reference/fbx_mixamo_vs_threejs.py). Skipped without the
# shared data.
add_test(NAME python.fbx_mixamo_vs_threejs
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/reference/fbx_mixamo_vs_threejs.py
    $<TARGET_FILE:armature-server> $<TARGET_FILE:armature> ${ARMATURE_SHARED_DATA})
set_tests_properties(python.fbx_mixamo_vs_threejs PROPERTIES TIMEOUT 300 SKIP_REGULAR_EXPRESSION "SKIP:")
