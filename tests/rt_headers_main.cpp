// SPDX-License-Identifier: MIT
/// @file The main of test_rt_headers_no_exceptions: the test is that every real-time header,
/// each in its own translation unit, compiled and linked with -fno-exceptions -fno-rtti.
int main() { return 0; }
