# glTF export (issue 14): .glb/.gltf files `armature export` writes from a BVH
# clip (CMU 01_01), a glTF clip with meshes (RobotExpressive) and the demo
# character load in three.js's GLTFLoader in node, and its AnimationMixer puts
# every joint where `armature pose --space world` does, within 1e-4 of the
# model's size (tests/reference/export_vs_threejs.py), with the clips kept
# exact and at the server's default bound. Skipped without the shared data.
add_test(NAME python.export_vs_threejs
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/reference/export_vs_threejs.py
    $<TARGET_FILE:armature-server> $<TARGET_FILE:armature> ${ARMATURE_SHARED_DATA} exact)
set_tests_properties(python.export_vs_threejs PROPERTIES TIMEOUT 300 SKIP_REGULAR_EXPRESSION "SKIP:")
add_test(NAME python.export_vs_threejs_default_bound
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/reference/export_vs_threejs.py
    $<TARGET_FILE:armature-server> $<TARGET_FILE:armature> ${ARMATURE_SHARED_DATA} default)
set_tests_properties(python.export_vs_threejs_default_bound PROPERTIES TIMEOUT 300 SKIP_REGULAR_EXPRESSION "SKIP:")
