/* stream.c - the memory sink for ls_write_fn writers. */
#include <string.h>
#include <largesteps/stream.h>

int32_t ls_membuf_write(void *user, const void *data, size_t bytes)
{
    ls_membuf *m = (ls_membuf *)user;
    if (m == NULL || (data == NULL && bytes > 0)) return 1;
    if (m->size > m->capacity || bytes > m->capacity - m->size) {
        m->overflow = 1;
        return 1;
    }
    if (bytes > 0) memcpy(m->data + m->size, data, bytes);
    m->size += bytes;
    return 0;
}
