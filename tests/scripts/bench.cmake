# scripts/bench_ratios.py (the Armature/ozz ratios `make bench` prints) on
# hand-made benchmark JSON. The ozz agreement check itself is
# bench.vs_ozz_agreement, registered by bench/ in builds with ozz.
add_test(NAME bench.ratios COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/bench/bench_ratios_test.py)
set_tests_properties(bench.ratios PROPERTIES TIMEOUT 60)
