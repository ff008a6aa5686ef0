/* Preloaded into the sanitized suite (scripts/test-sanitized.sh): shared
 * objects are never unloaded. Mesa's software driver (swrast_dri.so) is
 * dlclosed at exit, before LeakSanitizer looks; the blocks it allocated
 * and kept in its own data then look leaked, with a stack of
 * "<unknown module>" that no suppression can name. */
int dlclose(void* handle) {
  (void)handle;
  return 0;
}
