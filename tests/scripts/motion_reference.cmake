# `armature pose --motion` joint world positions against three.js's own
# AnimationMixer in node (tests/reference/motion_reference.mjs) on
# RobotExpressive: PHASE and NONE sync, total weight below 1, additive
# layers, masks; within 1e-4 of the model's size. Skipped without the file.
add_test(NAME python.motion_vs_threejs
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/reference/motion_vs_threejs.py
    $<TARGET_FILE:armature-server> $<TARGET_FILE:armature> ${ARMATURE_SHARED_DATA})
set_tests_properties(python.motion_vs_threejs PROPERTIES TIMEOUT 300 SKIP_REGULAR_EXPRESSION "SKIP:")
