# Included by CTest (TEST_INCLUDE_FILES, tests/CMakeLists.txt) after the GoogleTest cases are
# discovered: the heavier cases keep their label and gain `heavy`, outside the quick set of
# tools/run-tests.sh (tests/README.md, "The quick set and the rest").
set_tests_properties(Rd0Rheology.ShearThinningDetectedAtPhi080 Massive.SmallMassRdReproducesRd0
  Minimize.SplitPositionsRemoveTheResolutionGradient PROPERTIES LABELS "physics;heavy")
