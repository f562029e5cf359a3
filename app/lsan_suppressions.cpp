/// LeakSanitizer's suppressions for the `granular` program, linked in the sanitize preset only
/// (app/CMakeLists.txt): Mesa 22.3's OSMesaMakeCurrent allocates a framebuffer per context that
/// OSMesaDestroyContext never frees (≈ 200 bytes per context, inside libOSMesa). Not ours;
/// without this a run that draws figures ends with exit 1 under LSan. The test binary has the
/// same hook (tests/test_particle_view.cpp).
extern "C" const char* __lsan_default_suppressions() {
  return "leak:libOSMesa.so\n";
}
