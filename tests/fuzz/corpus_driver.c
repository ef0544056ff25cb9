/* Runs a fuzz target's seed corpus as an ordinary test (ctest fuzz_corpus_*,
 * in every build, the sanitizers' included): each file under the folders
 * or files named on the command line is given once to the target's
 * LLVMFuzzerTestOneInput, as libFuzzer would.  A crash, a sanitizer report
 * or a trap fails the test; so do an unreadable input and a corpus with no
 * file at all (a test that ran nothing).  libFuzzer itself runs the targets
 * for a bounded time in scripts/fuzz.sh. */
#include <dirent.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static int run_file(const char *path) {
  FILE *f = fopen(path, "rb");
  if (!f) {
    perror(path);
    return -1;
  }
  size_t cap = 1 << 16, n = 0;
  uint8_t *buf = malloc(cap);
  for (size_t got; buf && (got = fread(buf + n, 1, cap - n, f)) > 0;) {
    n += got;
    if (n == cap) {
      uint8_t *grown = realloc(buf, cap *= 2);
      if (!grown) free(buf);
      buf = grown;
    }
  }
  int bad = ferror(f) || !buf;
  fclose(f);
  if (bad) {
    fprintf(stderr, "%s: cannot read\n", path);
    free(buf);
    return -1;
  }
  /* As libFuzzer gives it (scripts/fuzz.sh: -max_len=65536): at most
   * 64 KiB, in a buffer of exactly that size, so that a read past the
   * input is past the allocation and the sanitizers see it. */
  if (n > 65536) n = 65536;
  uint8_t *exact = malloc(n ? n : 1);
  if (!exact) {
    free(buf);
    return -1;
  }
  memcpy(exact, buf, n);
  free(buf);
  LLVMFuzzerTestOneInput(exact, n);
  free(exact);
  return 1;
}

static int run_path(const char *path) {
  struct stat sb;
  if (lstat(path, &sb) != 0) {
    perror(path);
    return -1;
  }
  if (S_ISLNK(sb.st_mode)) return 0; /* a corpus holds files, not links */
  if (!S_ISDIR(sb.st_mode)) return run_file(path);
  DIR *d = opendir(path);
  if (!d) {
    perror(path);
    return -1;
  }
  int count = 0;
  for (struct dirent *e; (e = readdir(d));) {
    if (e->d_name[0] == '.') continue;
    char sub[4096];
    if (snprintf(sub, sizeof sub, "%s/%s", path, e->d_name) >= (int)sizeof sub) {
      fprintf(stderr, "%s/%s: path too long\n", path, e->d_name);
      count = -1;
      break;
    }
    int k = run_path(sub);
    if (k < 0) {
      count = -1;
      break;
    }
    count += k;
  }
  closedir(d);
  return count;
}

int main(int argc, char **argv) {
  int total = 0;
  for (int i = 1; i < argc; i++) {
    int k = run_path(argv[i]);
    if (k < 0) return 1;
    total += k;
  }
  printf("%d corpus inputs ran\n", total);
  if (total == 0) {
    fprintf(stderr, "no corpus input found: the test would have run nothing\n");
    return 1;
  }
  return 0;
}
