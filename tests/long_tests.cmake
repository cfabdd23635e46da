# Read by ctest after the discovered GoogleTest tests (TEST_INCLUDE_FILES,
# tests/CMakeLists.txt): the costs, in seconds on a 2-core machine, of the
# longest acceptance tests, so that ctest -j starts them first in a fresh
# build tree, which has no timings of its own yet. Started last, the ring's
# two minutes would run alone at the end.
set_tests_properties(RemeshScenes.RingTo60PercentWhicheverTheCriteria PROPERTIES COST 150)
set_tests_properties(RemeshScenes.BackwardExtrusionOfACup PROPERTIES COST 40)
