# The README's tour, run like code: every command between its tour markers
# against a real server on free ports (tests/docs/readme_tour.py). Commands
# marked "# tour: needs <feature>" are skipped and listed in the output.
add_test(NAME docs.readme_tour
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/docs/readme_tour.py
    $<TARGET_FILE:armature-server> $<TARGET_FILE_DIR:armature> ${CMAKE_SOURCE_DIR}/README.md)
set_tests_properties(docs.readme_tour PROPERTIES TIMEOUT 300)
# The runner itself: a tour whose third command fails is reported with its
# README line and text, the marked command skipped, nothing after it run.
add_test(NAME docs.readme_tour_runner
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/docs/readme_tour_selftest.py)
set_tests_properties(docs.readme_tour_runner PROPERTIES TIMEOUT 60)
# Relative links and #anchors of README.md, ARCHITECTURE.md and docs/ resolve.
add_test(NAME docs.links COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/docs/check_links.py ${CMAKE_SOURCE_DIR})
set_tests_properties(docs.links PROPERTIES TIMEOUT 60)
# The README's Python client steps, literally, in a clean folder with no package
# index, then its example against a real server; the Debian packages it names
# are among those `make run` installs.
add_test(NAME docs.readme_python_install
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/docs/readme_python_install.py
    $<TARGET_FILE:armature-server> ${CMAKE_SOURCE_DIR})
set_tests_properties(docs.readme_python_install PROPERTIES TIMEOUT 300 SKIP_REGULAR_EXPRESSION "SKIP:")
