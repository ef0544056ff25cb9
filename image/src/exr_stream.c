/* OpenEXR core streams shared by image_exr.c and spectral_exr.c (see
 * exr_stream.h). */
#include "exr_stream.h"

#include <errno.h>
#include <string.h>
#include <sys/types.h>

int64_t vr_exr_stream_read(exr_const_context_t ctxt, void *user, void *buffer, uint64_t sz,
                           uint64_t offset, exr_stream_error_func_ptr_t error_cb) {
  (void)ctxt;
  (void)error_cb;
  const exr_stream *s = user;
  if (offset >= s->len) return 0;
  uint64_t n = s->len - offset < sz ? s->len - offset : sz;
  memcpy(buffer, s->buf + offset, (size_t)n);
  return (int64_t)n;
}

int64_t vr_exr_stream_size(exr_const_context_t ctxt, void *user) {
  (void)ctxt;
  return (int64_t)((const exr_stream *)user)->len;
}

int64_t vr_exr_stream_write(exr_const_context_t ctxt, void *user, const void *buffer, uint64_t sz,
                            uint64_t offset, exr_stream_error_func_ptr_t error_cb) {
  (void)ctxt;
  (void)error_cb;
  exr_stream *s = user;
  if (fseeko(s->fp, (off_t)offset, SEEK_SET) != 0 || fwrite(buffer, 1, sz, s->fp) != sz) {
    if (!s->write_errno) s->write_errno = errno ? errno : EIO;
    return -1;
  }
  if (s->af) vr_atomic_file_writeback(s->af, (long long)(offset + sz));
  return (int64_t)sz;
}

/* Read contexts are not locked, so asking for the user data here is safe. */
void vr_exr_on_read_error(exr_const_context_t ctxt, exr_result_t code, const char *msg) {
  void *user = NULL;
  if (!ctxt || exr_get_user_data(ctxt, &user) != EXR_ERR_SUCCESS || !user) return;
  exr_stream *s = user;
  if (!s->message[0])
    snprintf(s->message, sizeof s->message, "%s", msg ? msg : exr_get_default_error_message(code));
}

/* Write contexts hold their lock while reporting, so this one must not call
 * back into OpenEXR; stream_write keeps the errno that matters. */
void vr_exr_on_write_error(exr_const_context_t ctxt, exr_result_t code, const char *msg) {
  (void)ctxt;
  (void)code;
  (void)msg;
}

vr_status vr_exr_read_failed(vr_error *err, const char *path, const exr_stream *s,
                             exr_result_t rv, const char *doing) {
  return vr_error_at(err, VR_E_PARSE, path, 0, 0, "OpenEXR: %s: %s", doing,
                     s->message[0] ? s->message : exr_get_default_error_message(rv));
}

int vr_exr_find_channel(const exr_attr_chlist_t *ch, const char *name) {
  for (int i = 0; i < ch->num_channels; i++)
    if (strcmp(ch->entries[i].name.str, name) == 0) return i;
  return -1;
}
