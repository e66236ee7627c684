# Read by ctest before the tests declared with add_test, after the discovered Google Tests
# (tests/CMakeLists.txt adds it to TEST_INCLUDE_FILES after gtest_discover_tests). ctest starts
# the costliest tests first, from the times it recorded on the previous run
# (Testing/Temporary/CTestCostData.txt). A fresh build, as CI's, has none: the tests start in
# the order they were declared, and the longest ones, started last, keep the run going on one
# core while the other idles. These costs are seconds measured in a fresh-clone run of
# scripts/test.sh on 2 cores (the sanitizer suite's, where these tests are slowest); only their
# order matters, and later runs use ctest's own timings. A name that is not a test is ignored.
# The costs of the tests declared with add_test are set beside them in tests/CMakeLists.txt.
set_tests_properties(MannequinGenerator.ReproducesAnsurSubjects PROPERTIES COST 38)
set_tests_properties(ShapeCount.CurveOnASmallSubset PROPERTIES COST 83)
set_tests_properties(MannequinGenerator.ShouldersBendWithoutFolding PROPERTIES COST 4)
set_tests_properties(MakeHumanFiles.AcceptsTheRepositoryDownloadAsItComes PROPERTIES COST 49)
set_tests_properties(Evaluation.NoiseIsSeededAndMatters PROPERTIES COST 32)
set_tests_properties(MakeHumanBuild.SmallPopulationGivesAModelAvatarsCanUse PROPERTIES COST 39)
