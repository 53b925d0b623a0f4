# libarmature-client installs and is usable from another CMake project
# through find_package(armature).
add_test(NAME client_package.find_package
  COMMAND ${CMAKE_COMMAND}
    -DBINARY_DIR=${CMAKE_BINARY_DIR}
    -DCONSUMER_DIR=${CMAKE_CURRENT_SOURCE_DIR}/package/consumer
    -DWORK_DIR=${CMAKE_CURRENT_BINARY_DIR}/package
    -P ${CMAKE_CURRENT_SOURCE_DIR}/package/run_consumer.cmake)
set_tests_properties(client_package.find_package PROPERTIES TIMEOUT 600)
