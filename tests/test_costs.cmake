# ctest -j2 starts the costliest tests first (after the fixtures' setups): with no cost data
# (a fresh clone, as CI's), it starts them in the order they were added, and a minute-long
# test added last (the installed Python package, 54 s) ran with one core idle at the end.
# The gtest tests' costs, in seconds from CI's plain run on a 2-vCPU EPYC (docs/drivers.md;
# gtest_discover_tests names a parameterised test with its parameter after "  # "). Read by
# ctest after the discovered tests and before tests/CMakeLists.txt's own, which set theirs
# there.
set(lava_test_costs
    "Commands/FaultInjection.EveryFailingCallExitsOneWithOneLineAndNoPartialOutput/render  # GetParam() = render" 67
    "Commands/FaultInjection.EveryFailingCallExitsOneWithOneLineAndNoPartialOutput/demo  # GetParam() = demo" 55
    GpuTest.ADispatchOfMoreThan2To31BirthsIsSplit 55
    "Commands/FaultInjection.EveryFailingCallExitsOneWithOneLineAndNoPartialOutput/bench  # GetParam() = bench" 49
    PublishedSolutions.NusseltsFilmAtAThousandSquareMetresASecondAtOneMillisecond 30
    PublishedSolutions.NusseltsFilmAtATenthOfASquareMetreASecond 30
    PublishedSolutions.HuppertsSpreadingPoolAtAFrame 29
    PublishedSolutions.NusseltsFilmAtTenSquareMetresASecond 24
    "Commands/FaultInjection.EveryFailingCallExitsOneWithOneLineAndNoPartialOutput/validate  # GetParam() = validate" 23
    PublishedSolutions.NusseltsFilmAtOneSquareMetreASecond 20)
while(lava_test_costs)
  list(POP_FRONT lava_test_costs name cost)
  # ctest passes over a name it does not have (the Python tests where the module is not built).
  set_tests_properties("${name}" PROPERTIES COST ${cost})
endwhile()
