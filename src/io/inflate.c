/* inflate.c - deflate (RFC 1951) and zlib (RFC 1950) decompression.
 *
 * One loop over blocks, no recursion. Huffman codes are canonical; each
 * table has a direct lookup of the first FAST_BITS bits and a bit-by-bit
 * canonical walk for longer codes. Input is read into a 64-bit buffer that a
 * refill tops up to at least 57 bits, enough for a whole length/distance
 * pair (15 + 5 + 15 + 13 bits); reading past the input loads zero bytes and
 * counts them (pad), and consuming any of them marks the stream truncated, so
 * every loop ends within the input's bits (each symbol consumes at least one
 * bit).
 */
#include <string.h>
#include "image_codec.h"

#define MAX_BITS 15u
#define FAST_BITS 9u
#define FAST_SIZE (1u << FAST_BITS)
#define LITLEN_SYMS 288u
#define DIST_SYMS 32u
#define CL_SYMS 19u

/* A canonical Huffman code. fast[b] for the next FAST_BITS input bits b is
 * (length << 9) | symbol, or 0 when the code is longer (or b starts no code). */
typedef struct huff {
    uint16_t count[MAX_BITS + 1u];  /* codes of each length */
    uint16_t symbol[LITLEN_SYMS];   /* symbols ordered by code */
    uint16_t fast[FAST_SIZE];
} huff;

typedef struct inflate_state {
    huff lit;
    huff dist;
    huff cl;
    uint8_t lengths[LITLEN_SYMS + DIST_SYMS];
} inflate_state;

typedef struct reader {
    ls_inflate_input *in;
    uint64_t buf;  /* bits not yet consumed, the next one in bit 0 */
    uint32_t cnt;  /* how many */
    uint32_t pad;  /* zero bytes loaded past the end of the input */
    uint32_t bad;  /* 1 once a padding bit was consumed */
} reader;

/* RFC 1951 3.2.5 and 3.2.7: also the compressor's (deflate.c). */
const uint16_t ls_deflate_len_base[29] = {3, 4, 5, 6, 7, 8, 9, 10, 11, 13, 15, 17, 19, 23, 27,
                                      31, 35, 43, 51, 59, 67, 83, 99, 115, 131, 163, 195, 227, 258};
const uint8_t ls_deflate_len_extra[29] = {0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2,
                                      2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0};
const uint16_t ls_deflate_dist_base[30] = {1, 2, 3, 4, 5, 7, 9, 13, 17, 25, 33, 49, 65, 97, 129,
                                       193, 257, 385, 513, 769, 1025, 1537, 2049, 3073, 4097,
                                       6145, 8193, 12289, 16385, 24577};
const uint8_t ls_deflate_dist_extra[30] = {0, 0, 0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6,
                                       6, 7, 7, 8, 8, 9, 9, 10, 10, 11, 11, 12, 12, 13, 13};
const uint8_t ls_deflate_cl_order[19] = {16, 17, 18, 0, 8, 7, 9, 6, 10, 5, 11, 4, 12, 3, 13, 2, 14, 1, 15};

size_t ls_inflate_state_bytes_(void)
{
    return sizeof(inflate_state);
}

/* Moves a PNG reader to the data of the next IDAT chunk (skipping empty ones);
 * 0 when the next chunk is not an IDAT (or the file ends). */
static int next_idat(ls_inflate_input *in)
{
    size_t p = in->end;
    for (;;) {
        uint32_t len;
        const unsigned char *h;
        if (p > in->file_bytes || in->file_bytes - p < 12u) return 0;
        h = in->file + p + 4u; /* after the CRC of the chunk that ended */
        if (h[4] != 'I' || h[5] != 'D' || h[6] != 'A' || h[7] != 'T') return 0;
        len = ((uint32_t)h[0] << 24) | ((uint32_t)h[1] << 16) | ((uint32_t)h[2] << 8) | h[3];
        if (len > in->file_bytes - p - 12u) return 0;
        in->pos = p + 12u;
        in->end = p + 12u + len;
        if (len > 0) return 1;
        p = in->end;
    }
}

/* The next input byte, or -1 at the end of the input. */
static int32_t input_byte(ls_inflate_input *in)
{
    if (in->pos >= in->end && !(in->png_idat && next_idat(in))) return -1;
    return in->file[in->pos++];
}

/* Tops the buffer up to at least 57 bits. */
static void refill(reader *r)
{
    ls_inflate_input *in = r->in;
    while (r->cnt <= 56u) {
        int32_t b;
        if (in->pos < in->end) {
            r->buf |= (uint64_t)in->file[in->pos++] << r->cnt;
            r->cnt += 8u;
            continue;
        }
        b = input_byte(in);
        if (b < 0) {
            b = 0;
            r->pad++;
        }
        r->buf |= (uint64_t)b << r->cnt;
        r->cnt += 8u;
    }
}

static void consume(reader *r, uint32_t n)
{
    r->buf >>= n; /* n <= 16 */
    r->cnt -= n;
    if (r->cnt < 8u * r->pad) r->bad = 1;
}

/* n <= 16 bits from the buffer (the caller has refilled enough). */
static uint32_t take(reader *r, uint32_t n)
{
    uint32_t v = (uint32_t)r->buf & ((1u << n) - 1u);
    consume(r, n);
    return v;
}

/* n <= 16 bits, first bit in bit 0, refilling first. */
static uint32_t getbits(reader *r, uint32_t n)
{
    refill(r);
    return take(r, n);
}

/* Byte offset of the reader in the input (approximate across IDAT chunks). */
static int64_t reader_offset(const reader *r)
{
    uint32_t buffered = r->cnt / 8u;
    uint32_t real = buffered > r->pad ? buffered - r->pad : 0u;
    size_t pos = r->in->pos;
    return (int64_t)(pos >= real ? pos - real : 0u);
}

/* Builds the tables of a code from its lengths. Returns 0, or 1 when the
 * lengths oversubscribe the code space, 2 when they leave it incomplete (only
 * allowed for a single code of length 1, or no code at all, except for the
 * code-length code which must be complete). */
static int huff_build(huff *h, const uint8_t *length, uint32_t n, int is_cl)
{
    uint16_t offs[MAX_BITS + 2u];
    int32_t left = 1;
    uint32_t sym, len, code, i, used = 0;
    memset(h->count, 0, sizeof h->count);
    for (sym = 0; sym < n; sym++) h->count[length[sym]]++;
    h->count[0] = 0;
    for (len = 1; len <= MAX_BITS; len++) {
        left = left * 2 - (int32_t)h->count[len];
        if (left < 0) return 1;
        used += h->count[len];
    }
    if (left > 0 && used > 0 && (is_cl || used != 1 || h->count[1] != 1)) return 2;
    offs[1] = 0;
    for (len = 1; len <= MAX_BITS; len++) offs[len + 1u] = (uint16_t)(offs[len] + h->count[len]);
    for (sym = 0; sym < n; sym++)
        if (length[sym] != 0) h->symbol[offs[length[sym]]++] = (uint16_t)sym;
    /* Direct lookup: walk the codes in canonical order. */
    memset(h->fast, 0, sizeof h->fast);
    code = 0;
    i = 0;
    for (len = 1; len <= FAST_BITS; len++) {
        uint32_t k;
        for (k = 0; k < h->count[len]; k++, i++, code++) {
            uint32_t rev = 0, b, fill;
            for (b = 0; b < len; b++) rev |= ((code >> b) & 1u) << (len - 1u - b);
            for (fill = rev; fill < FAST_SIZE; fill += 1u << len)
                h->fast[fill] = (uint16_t)((len << 9) | h->symbol[i]);
        }
        code <<= 1;
    }
    return 0;
}

/* The next symbol of code h, or -1 for a bit pattern that is no code (the
 * caller has refilled: at least 15 bits are buffered). */
static int32_t decode(reader *r, const huff *h)
{
    uint32_t e, code = 0, first = 0, index = 0, len;
    e = h->fast[(uint32_t)r->buf & (FAST_SIZE - 1u)];
    if (e != 0) {
        consume(r, e >> 9);
        return (int32_t)(e & 511u);
    }
    for (len = 1; len <= MAX_BITS; len++) {
        uint32_t count = h->count[len];
        code |= (uint32_t)(r->buf >> (len - 1u)) & 1u;
        if (code < first + count) {
            consume(r, len);
            return (int32_t)h->symbol[index + code - first];
        }
        index += count;
        first = (first + count) << 1;
        code <<= 1;
    }
    return -1;
}

static void build_fixed(inflate_state *s)
{
    uint32_t i;
    for (i = 0; i < 144u; i++) s->lengths[i] = 8;
    for (; i < 256u; i++) s->lengths[i] = 9;
    for (; i < 280u; i++) s->lengths[i] = 7;
    for (; i < LITLEN_SYMS; i++) s->lengths[i] = 8;
    (void)huff_build(&s->lit, s->lengths, LITLEN_SYMS, 0);
    for (i = 0; i < DIST_SYMS; i++) s->lengths[i] = 5;
    (void)huff_build(&s->dist, s->lengths, DIST_SYMS, 0);
}

#define FAIL_AT(what_) return ls_image_fail_(diag, LS_ERR_PARSE, (what_), reader_offset(r))
#define TRUNCATED "deflate stream truncated"

static ls_status build_dynamic(reader *r, inflate_state *s, ls_diag *diag)
{
    uint32_t hlit, hdist, hclen, i, total;
    int rc;
    hlit = getbits(r, 5) + 257u;
    hdist = getbits(r, 5) + 1u;
    hclen = getbits(r, 4) + 4u;
    if (r->bad) FAIL_AT(TRUNCATED);
    if (hlit > 286u) FAIL_AT("deflate dynamic block: more than 286 literal/length codes");
    if (hdist > 30u) FAIL_AT("deflate dynamic block: more than 30 distance codes");
    memset(s->lengths, 0, CL_SYMS);
    for (i = 0; i < hclen; i++) s->lengths[ls_deflate_cl_order[i]] = (uint8_t)getbits(r, 3);
    if (r->bad) FAIL_AT(TRUNCATED);
    if (huff_build(&s->cl, s->lengths, CL_SYMS, 1) != 0)
        FAIL_AT("deflate dynamic block: invalid code-length code lengths");
    total = hlit + hdist;
    i = 0;
    while (i < total) {
        int32_t sym;
        refill(r);
        sym = decode(r, &s->cl);
        uint32_t rep, val;
        if (r->bad) FAIL_AT(TRUNCATED);
        if (sym < 0) FAIL_AT("deflate dynamic block: invalid code-length code");
        if (sym < 16) {
            s->lengths[i++] = (uint8_t)sym;
            continue;
        }
        if (sym == 16) {
            if (i == 0) FAIL_AT("deflate dynamic block: repeat code 16 with no previous length");
            val = s->lengths[i - 1u];
            rep = 3u + take(r, 2);
        } else if (sym == 17) {
            val = 0;
            rep = 3u + take(r, 3);
        } else {
            val = 0;
            rep = 11u + take(r, 7);
        }
        if (r->bad) FAIL_AT(TRUNCATED);
        if (rep > total - i) FAIL_AT("deflate dynamic block: code-length repeat past the last code");
        while (rep-- > 0) s->lengths[i++] = (uint8_t)val;
    }
    if (s->lengths[256] == 0) FAIL_AT("deflate dynamic block: no end-of-block code");
    rc = huff_build(&s->lit, s->lengths, hlit, 0);
    if (rc == 1) FAIL_AT("deflate dynamic block: literal/length code lengths oversubscribed");
    if (rc == 2) FAIL_AT("deflate dynamic block: literal/length code lengths incomplete");
    rc = huff_build(&s->dist, s->lengths + hlit, hdist, 0);
    if (rc == 1) FAIL_AT("deflate dynamic block: distance code lengths oversubscribed");
    if (rc == 2) FAIL_AT("deflate dynamic block: distance code lengths incomplete");
    return LS_OK;
}

static ls_status inflate_codes(reader *r, const inflate_state *s, unsigned char *dst, size_t cap,
                               size_t *out, ls_diag *diag)
{
    size_t o = *out;
    for (;;) {
        int32_t sym;
        uint32_t len, dist;
        refill(r); /* enough for a literal, or a length and a distance with their extra bits */
        sym = decode(r, &s->lit);
        if (r->bad) FAIL_AT(TRUNCATED);
        if (sym < 0) FAIL_AT("deflate: invalid literal/length code");
        if (sym < 256) {
            if (o >= cap) break;
            dst[o++] = (unsigned char)sym;
            continue;
        }
        if (sym == 256) {
            *out = o;
            return LS_OK;
        }
        sym -= 257;
        if (sym >= 29) FAIL_AT("deflate: invalid length symbol (286 or 287)");
        len = ls_deflate_len_base[sym] + take(r, ls_deflate_len_extra[sym]);
        sym = decode(r, &s->dist);
        if (r->bad) FAIL_AT(TRUNCATED);
        if (sym < 0) FAIL_AT("deflate: invalid distance code");
        if (sym >= 30) FAIL_AT("deflate: invalid distance symbol (30 or 31)");
        dist = ls_deflate_dist_base[sym] + take(r, ls_deflate_dist_extra[sym]);
        if (r->bad) FAIL_AT(TRUNCATED);
        if (dist > o) FAIL_AT("deflate: distance too far back");
        if (len > cap - o) break;
        {
            const unsigned char *from = dst + (o - dist);
            unsigned char *to = dst + o;
            uint32_t k;
            for (k = 0; k < len; k++) to[k] = from[k];
            o += len;
        }
    }
    return ls_image_fail_(diag, LS_ERR_TOO_LARGE, "deflate: output longer than expected", reader_offset(r));
}

static ls_status inflate_stored(reader *r, unsigned char *dst, size_t cap, size_t *out, ls_diag *diag)
{
    uint32_t len, nlen;
    size_t o = *out;
    consume(r, r->cnt & 7u);
    len = getbits(r, 16);
    nlen = getbits(r, 16);
    if (r->bad) FAIL_AT(TRUNCATED);
    if (len != (~nlen & 0xffffu)) FAIL_AT("deflate stored block: length does not match its complement");
    if (len > cap - o)
        return ls_image_fail_(diag, LS_ERR_TOO_LARGE, "deflate: output longer than expected", reader_offset(r));
    while (len > 0 && r->cnt >= 8u) {
        if (r->cnt / 8u <= r->pad) FAIL_AT(TRUNCATED);
        dst[o++] = (unsigned char)(r->buf & 0xffu);
        consume(r, 8);
        len--;
    }
    while (len > 0) {
        ls_inflate_input *in = r->in;
        size_t n;
        if (in->pos >= in->end && !(in->png_idat && next_idat(in))) FAIL_AT(TRUNCATED);
        n = in->end - in->pos;
        if (n > len) n = len;
        memcpy(dst + o, in->file + in->pos, n);
        in->pos += n;
        o += n;
        len -= (uint32_t)n;
    }
    *out = o;
    return LS_OK;
}

ls_status ls_inflate_run_(ls_inflate_input *in, void *state, ls_diag *diag)
{
    inflate_state *s = (inflate_state *)state;
    reader rd, *r = &rd;
    unsigned char *dst = in->dst;
    size_t out = 0, cap = in->cap;
    uint32_t final;
    ls_status st;
    rd.in = in;
    rd.buf = 0;
    rd.cnt = 0;
    rd.pad = 0;
    rd.bad = 0;
    in->produced = 0;
    if (in->zlib) {
        uint32_t cmf = getbits(r, 8), flg = getbits(r, 8);
        if (r->bad) FAIL_AT("zlib stream truncated in its header");
        if ((cmf & 15u) != 8u) FAIL_AT("zlib header: compression method is not deflate");
        if ((cmf >> 4) > 7u) FAIL_AT("zlib header: window larger than 32 KB");
        if ((cmf * 256u + flg) % 31u != 0) FAIL_AT("zlib header: check bits wrong");
        if (flg & 0x20u)
            return ls_image_fail_(diag, LS_ERR_UNSUPPORTED, "zlib preset dictionary", reader_offset(r));
    }
    do {
        uint32_t type;
        final = getbits(r, 1);
        type = getbits(r, 2);
        if (r->bad) FAIL_AT(TRUNCATED);
        if (type == 0) {
            st = inflate_stored(r, dst, cap, &out, diag);
        } else if (type == 1) {
            build_fixed(s);
            st = inflate_codes(r, s, dst, cap, &out, diag);
        } else if (type == 2) {
            st = build_dynamic(r, s, diag);
            if (st == LS_OK) st = inflate_codes(r, s, dst, cap, &out, diag);
        } else {
            FAIL_AT("deflate: invalid block type 3");
        }
        if (st != LS_OK) return st;
    } while (!final);
    consume(r, r->cnt & 7u); /* to a byte boundary */
    if (r->bad) FAIL_AT(TRUNCATED);
    if (in->zlib) {
        uint32_t want = 0, k;
        for (k = 0; k < 4u; k++) want = (want << 8) | getbits(r, 8);
        if (r->bad) FAIL_AT("zlib stream truncated in its Adler-32");
        if (want != ls_adler32(1u, dst, out)) FAIL_AT("zlib Adler-32 mismatch");
    }
    if (r->cnt / 8u > r->pad || input_byte(in) >= 0) FAIL_AT("bytes after the end of the deflate stream");
    in->produced = out;
    return LS_OK;
}

static void set_input(ls_inflate_input *in, const void *src, size_t src_bytes, void *dst, size_t dst_bytes)
{
    in->file = (const unsigned char *)src;
    in->file_bytes = src_bytes;
    in->pos = 0;
    in->end = src_bytes;
    in->png_idat = 0;
    in->zlib = 0;
    in->dst = (unsigned char *)dst;
    in->cap = dst_bytes;
    in->produced = 0;
}

static ls_status run_public(ls_inflate_input *in, size_t *out_bytes, ls_arena *arena, ls_diag *diag)
{
    ls_arena_mark mark;
    void *state;
    ls_status st;
    if (out_bytes != NULL) *out_bytes = 0;
    if (in->file == NULL && in->file_bytes > 0)
        return ls_image_fail_(diag, LS_ERR_INVALID, "src is NULL with src_bytes > 0", -1);
    if (in->dst == NULL && in->cap > 0) return ls_image_fail_(diag, LS_ERR_INVALID, "dst is NULL with dst_bytes > 0", -1);
    if (out_bytes == NULL) return ls_image_fail_(diag, LS_ERR_INVALID, "out_bytes is NULL", -1);
    if (arena == NULL) return ls_image_fail_(diag, LS_ERR_INVALID, "arena is NULL", -1);
    mark = ls_arena_save(arena);
    state = ls_arena_scratch(arena, 1, sizeof(inflate_state));
    if (state == NULL) return ls_image_fail_(diag, LS_ERR_NOMEM, "arena too small for the inflate state", -1);
    st = ls_inflate_run_(in, state, diag);
    *out_bytes = in->produced;
    ls_arena_restore(arena, mark);
    return st;
}

ls_status ls_inflate_bytes(size_t *arena_bytes)
{
    if (arena_bytes == NULL) return LS_ERR_INVALID;
    *arena_bytes = LS_ARENA_ROUND(sizeof(inflate_state));
    return LS_OK;
}

ls_status ls_zlib_decompress(const void *src, size_t src_bytes, void *dst, size_t dst_bytes,
                             size_t *out_bytes, ls_arena *arena, ls_diag *diag)
{
    ls_diag_clear(diag);
    ls_inflate_input in;
    set_input(&in, src, src_bytes, dst, dst_bytes);
    in.zlib = 1;
    return run_public(&in, out_bytes, arena, diag);
}

ls_status ls_inflate(const void *src, size_t src_bytes, void *dst, size_t dst_bytes,
                     size_t *out_bytes, ls_arena *arena, ls_diag *diag)
{
    ls_diag_clear(diag);
    ls_inflate_input in;
    set_input(&in, src, src_bytes, dst, dst_bytes);
    return run_public(&in, out_bytes, arena, diag);
}
