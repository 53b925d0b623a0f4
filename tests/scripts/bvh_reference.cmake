# `armature pose` world positions against an independent SciPy forward
# kinematics, for the CMU capture and re-ordered copies of it.
add_test(NAME python.cli_pose_vs_scipy_reference
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/reference/cli_pose_vs_reference.py
    $<TARGET_FILE:armature-server> $<TARGET_FILE:armature> ${ARMATURE_SHARED_DATA})
set_tests_properties(python.cli_pose_vs_scipy_reference PROPERTIES TIMEOUT 300 SKIP_REGULAR_EXPRESSION "SKIP:")
