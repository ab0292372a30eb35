// Compiled only to carry a precompiled header that other targets reuse (CMakeLists.txt, KINCAL_PCH).
