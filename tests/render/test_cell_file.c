/* A sub-domain's cell file as a load reads it (vr_cell_file_read in
 * render/src/geometry/cache_format.c): mapped from the file, not copied.
 *
 * What is checked, against the bytes written (not against the reader):
 *   - the payload comes back byte for byte, 64-byte aligned, and its XXH64
 *     is the one the writer returned (XXH64 itself is held to its
 *     specification's vectors in tests/core/test_plumbing.c);
 *   - a second read of the same file gives the same bytes;
 *   - a file replaced by rename while mapped (how the cache's writers
 *     replace files) leaves the mapping with the bytes it mapped;
 *   - a payload byte changed on disk is VR_E_PARSE "damaged (checksum of
 *     its contents)", a file cut short "truncated", and neither maps
 *     anything (*payload stays NULL). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <fcntl.h>
#include <unistd.h>

#include <cmocka.h>

#include "geometry/cache_format.h"
#include "vr/hash64.h"

static const uint8_t KEY[32] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10};

/* A cell of n triangles on n + 2 vertices, its payload filled with a
 * pattern (the reader checks the layout's size, not the arrays' sense). */
static vr_cell_meta meta_of(uint64_t ntris) {
  vr_cell_meta m = {0};
  m.nverts = ntris + 2;
  m.ntris = ntris;
  vr_cell_layout L;
  assert_true(vr_cell_layout_of(m.nverts, m.ntris, 0, 0, &L));
  m.payload_bytes = L.total;
  return m;
}

static unsigned char *pattern(size_t n, unsigned seed) {
  unsigned char *p = malloc(n);
  for (size_t i = 0; i < n; i++) p[i] = (unsigned char)((i * 2654435761u + seed) >> 7);
  return p;
}

/* Changes the byte `back` bytes before the end of the file, in place. */
static void damage_near_end(const char *path, long back) {
  int fd = open(path, O_RDWR);
  assert_true(fd >= 0);
  off_t at = lseek(fd, 0, SEEK_END) - back;
  unsigned char b = 0;
  assert_int_equal(pread(fd, &b, 1, at), 1);
  b = (unsigned char)~b;
  assert_int_equal(pwrite(fd, &b, 1, at), 1);
  close(fd);
}

static void mapped_payload(void **state) {
  (void)state;
  char dir[] = "/tmp/vr_cell_file_XXXXXX", path[128], other[128];
  assert_non_null(mkdtemp(dir));
  snprintf(path, sizeof path, "%s/cell-00003.vrc", dir);
  snprintf(other, sizeof other, "%s/other.vrc", dir);
  vr_cell_meta m = meta_of(100000);
  unsigned char *bytes = pattern(m.payload_bytes, 7);
  vr_error err = {0};
  assert_int_equal(vr_cell_file_write(path, 3, KEY, &m, bytes, &m.payload_hash, &err), VR_OK);
  assert_true(m.payload_hash == vr_hash64_buffer(bytes, m.payload_bytes, 0));

  void *p = NULL;
  assert_int_equal(vr_cell_file_read(path, 3, KEY, &m, &p, &err), VR_OK);
  assert_non_null(p);
  assert_int_equal((uintptr_t)p % 64, 0);
  assert_memory_equal(p, bytes, m.payload_bytes);

  /* A second reader of the same file sees the same bytes. */
  void *q = NULL;
  assert_int_equal(vr_cell_file_read(path, 3, KEY, &m, &q, &err), VR_OK);
  assert_memory_equal(q, bytes, m.payload_bytes);
  vr_cell_file_release(p, &m);

  /* Replaced by rename under the mapping: the mapping keeps its bytes. */
  vr_cell_meta m2 = m;
  unsigned char *bytes2 = pattern(m.payload_bytes, 99);
  assert_int_equal(vr_cell_file_write(other, 3, KEY, &m2, bytes2, &m2.payload_hash, &err), VR_OK);
  assert_int_equal(rename(other, path), 0);
  assert_memory_equal(q, bytes, m.payload_bytes);
  vr_cell_file_release(q, &m);
  /* The manifest's record is the old file's: the new one is refused by
   * its header, which holds the contents' checksum. */
  void *r = (void *)1;
  assert_int_equal(vr_cell_file_read(path, 3, KEY, &m, &r, &err), VR_E_PARSE);
  assert_null(r);
  assert_non_null(strstr(err.message, "cell-00003.vrc"));
  r = NULL;
  assert_int_equal(vr_cell_file_read(path, 3, KEY, &m2, &r, &err), VR_OK);
  assert_memory_equal(r, bytes2, m.payload_bytes);
  vr_cell_file_release(r, &m2);

  /* A byte changed in the contents, then the file cut short. */
  damage_near_end(path, 5);
  r = (void *)1;
  assert_int_equal(vr_cell_file_read(path, 3, KEY, &m2, &r, &err), VR_E_PARSE);
  assert_null(r);
  assert_non_null(strstr(err.message, "damaged (checksum of its contents)"));
  assert_int_equal(truncate(path, VR_CELL_HEADER + 1000), 0);
  r = (void *)1;
  assert_int_equal(vr_cell_file_read(path, 3, KEY, &m2, &r, &err), VR_E_PARSE);
  assert_null(r);
  assert_non_null(strstr(err.message, "truncated"));
  vr_cell_file_release(NULL, &m2);

  unlink(path);
  rmdir(dir);
  free(bytes);
  free(bytes2);
}

/* An empty cell (no primitives) maps its header alone. */
static void empty_cell(void **state) {
  (void)state;
  char dir[] = "/tmp/vr_cell_file_XXXXXX", path[128];
  assert_non_null(mkdtemp(dir));
  snprintf(path, sizeof path, "%s/cell-00000.vrc", dir);
  vr_cell_meta m = {0};
  vr_cell_layout L;
  assert_true(vr_cell_layout_of(0, 0, 0, 0, &L));
  m.payload_bytes = L.total;
  unsigned char *bytes = pattern(m.payload_bytes ? m.payload_bytes : 1, 3);
  vr_error err = {0};
  assert_int_equal(vr_cell_file_write(path, 0, KEY, &m, bytes, &m.payload_hash, &err), VR_OK);
  void *p = NULL;
  assert_int_equal(vr_cell_file_read(path, 0, KEY, &m, &p, &err), VR_OK);
  assert_non_null(p);
  if (m.payload_bytes) assert_memory_equal(p, bytes, m.payload_bytes);
  vr_cell_file_release(p, &m);
  unlink(path);
  rmdir(dir);
  free(bytes);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(mapped_payload),
      cmocka_unit_test(empty_cell),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
