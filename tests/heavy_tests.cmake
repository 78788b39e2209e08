# Included by CTest (TEST_INCLUDE_FILES, tests/CMakeLists.txt) after the GoogleTest cases are
# discovered: the heavier cases keep their label and gain `heavy`, outside the quick set of
# tools/run-tests.sh (tests/README.md, "The quick set and the rest").
set_tests_properties(Rd0Rheology.ShearThinningDetectedAtPhi080 Massive.SmallMassRdReproducesRd0
  Minimize.SplitPositionsRemoveTheResolutionGradient PROPERTIES LABELS "physics;heavy")
# A CD0 replica on 1 to 4 threads: about 35 s on 2 cores (the RD0 one stays in the quick set).
set_tests_properties(Threads.Cd0ReplicaIsTheSameOnAnyThreadCount PROPERTIES LABELS "unit;heavy")
