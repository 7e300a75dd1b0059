/// @file test_pch.cpp
/// The unit that carries the test executables' precompiled header (GoogleTest and Eigen;
/// tests/CMakeLists.txt, SUITE_TEST_PCH): no code of its own.
