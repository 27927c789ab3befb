"""Helpers shared by tests/, bench/ and povray_patch/ (see tests/support/CMakeLists.txt)."""
