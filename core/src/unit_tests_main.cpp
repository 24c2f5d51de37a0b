// The doctest runner of the core's C++ unit tests (the *_test.cpp files beside
// the code they test). Built only with -DGRIDWALK_UNIT_TESTS=ON; run by
// tests/test00_core_unit_tests.py.
#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <doctest/doctest.h>
