# The container image end to end (deploy/image-test.sh, as `make image-test`):
# a real multi-stage podman build, the image run and checked from the host,
# the Kubernetes manifests validated. Skipped with a message without podman.
# Run alone: it compiles the server again inside the image build.
add_test(NAME deploy.image_test
  COMMAND ${CMAKE_SOURCE_DIR}/deploy/image-test.sh --cli $<TARGET_FILE:armature>)
set_tests_properties(deploy.image_test PROPERTIES TIMEOUT 3000 RUN_SERIAL TRUE SKIP_REGULAR_EXPRESSION "SKIP:")
