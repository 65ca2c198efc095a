/* deflate.c - deflate compression (RFC 1951), the encoder behind the PNG
 * writer.
 *
 * LZ77: hash chains over a 32 KiB window (3-byte hash, 2^15 heads), zlib's
 * lazy matching with its per-level parameters (good, lazy and nice lengths,
 * chain limit), matches at most MAX_DIST back. Blocks end when the symbol
 * buffer is full, when the window must slide past the block's first byte,
 * or at the end; each is written as the smallest of a stored, a fixed-Huffman
 * and a dynamic-Huffman block, so the output never exceeds
 * ls_deflate_bound_(). Huffman code lengths are limited (15 bits, 7 for the
 * code-length code) without recursion: symbols sorted by frequency with the
 * library's stable sort, a two-queue Huffman tree built in one loop, depths
 * set from the root down, lengths clamped and the Kraft sum repaired, then
 * handed out by rank. All memory is the caller's (ls_deflate_state_bytes_);
 * the bytes depend only on the input and the level.
 */
#include <string.h>
#include <largesteps/sort.h>
#include "image_codec.h"

#define WSIZE 32768u
#define WMASK (WSIZE - 1u)
#define HSIZE 32768u
#define HMASK (HSIZE - 1u)
#define MIN_MATCH 3u
#define MAX_MATCH 258u
#define MIN_LOOKAHEAD (MAX_MATCH + MIN_MATCH + 1u)
#define MAX_DIST (WSIZE - MIN_LOOKAHEAD)
#define TOO_FAR 4096u      /* a 3-byte match farther back is not worth it */
#define SYMS 16384u        /* symbols per block at most */
#define LL_SYMS 286u       /* literal/length symbols that may occur */
#define FIXED_LL 288u      /* the fixed code's literal/length alphabet */
#define D_SYMS 30u
#define CL_SYMS 19u
#define MAX_BITS 15u
#define CL_MAX_BITS 7u
#define OUT_BYTES 1024u
#define STORED_MAX 65535u
#define NODES (2u * FIXED_LL)


/* zlib's parameters per level: good, lazy, nice, chain. */
static const uint16_t level_params[9][4] = {
    {4, 4, 8, 4}, {4, 5, 16, 8}, {4, 6, 32, 32}, {4, 4, 16, 16}, {8, 16, 32, 32},
    {8, 16, 128, 128}, {8, 32, 128, 256}, {32, 128, 258, 1024}, {32, 258, 258, 4096}};

/* A Huffman code: lengths and bit-reversed codes (deflate sends codes
 * first bit first, into a stream read from bit 0). */
typedef struct huff_code {
    uint16_t code[FIXED_LL];
    uint8_t len[FIXED_LL];
} huff_code;

typedef struct deflate_state {
    ls_deflate_out_fn out;
    void *ctx;
    uint32_t good, lazy, nice, chain;
    uint32_t strstart;        /* next position to match */
    uint32_t lookahead;       /* bytes from strstart to the end of the input so far */
    uint32_t block_start;     /* window position of the block's first byte */
    uint32_t block_raw;       /* input bytes covered by the block's symbols */
    uint32_t match_length, match_start, prev_length, prev_match, match_available;
    uint32_t nsyms;
    uint32_t bitbuf, nbits;   /* fewer than 8 bits between calls */
    uint32_t outn;
    uint32_t lit_freq[FIXED_LL];
    uint32_t dist_freq[D_SYMS];
    uint32_t cl_freq[CL_SYMS];
    huff_code lit, dist, cl, fixed_lit, fixed_dist;
    /* tree building */
    uint32_t keys[FIXED_LL], idx[FIXED_LL], sort_scratch[FIXED_LL];
    uint32_t weight[NODES];
    uint16_t parent[NODES], depth[NODES];
    uint16_t bl_count[NODES];
    /* the code lengths run-length coded: symbols and their extra values */
    uint8_t cl_sym[LL_SYMS + D_SYMS], cl_val[LL_SYMS + D_SYMS];
    uint32_t ncl;
    uint16_t sym_dist[SYMS]; /* 0 for a literal */
    uint8_t sym_ll[SYMS];    /* the literal, or the match length - 3 */
    uint16_t head[HSIZE];
    uint16_t prev[WSIZE];
    unsigned char window[2u * WSIZE];
    unsigned char outbuf[OUT_BYTES];
} deflate_state;

size_t ls_deflate_state_bytes_(void)
{
    return sizeof(deflate_state);
}

ls_status ls_deflate_bound_(size_t n, size_t *bytes)
{
    /* blocks: one per SYMS symbols (each covers >= 1 byte), one per window
     * slide, the last; each at most 2 stored pieces of 5 header bytes (a
     * block never covers more than 2 * WSIZE bytes); 2 for an empty last block */
    size_t blocks = n / SYMS + n / WSIZE + 1u, t;
    if (ls_size_mul(blocks, 10u, &t) != LS_OK || ls_size_sum(t, n, &t) != LS_OK || ls_size_sum(t, 2u, bytes) != LS_OK)
        return LS_ERR_TOO_LARGE;
    return LS_OK;
}

/* --- bits out ------------------------------------------------------------- */

static void out_byte(deflate_state *s, uint32_t b)
{
    s->outbuf[s->outn++] = (unsigned char)b;
    if (s->outn == OUT_BYTES) {
        s->out(s->ctx, s->outbuf, s->outn);
        s->outn = 0;
    }
}

static void put_bits(deflate_state *s, uint32_t v, uint32_t n)
{
    s->bitbuf |= v << s->nbits;
    s->nbits += n;
    while (s->nbits >= 8u) {
        out_byte(s, s->bitbuf & 0xffu);
        s->bitbuf >>= 8;
        s->nbits -= 8u;
    }
}

static void align_byte(deflate_state *s)
{
    if (s->nbits > 0) out_byte(s, s->bitbuf & 0xffu);
    s->bitbuf = 0;
    s->nbits = 0;
}

/* --- codes ---------------------------------------------------------------- */

static uint32_t floor_log2(uint32_t v)
{
    uint32_t n = 0;
    while (v > 1u) {
        v >>= 1;
        n++;
    }
    return n;
}

/* Length 3..258 -> length code 0..28. */
static uint32_t length_code(uint32_t len)
{
    uint32_t l = len - 3u, n;
    if (l < 8u) return l;
    if (len == 258u) return 28u;
    n = floor_log2(l);
    return 4u * (n - 1u) + ((l >> (n - 2u)) & 3u);
}

/* Distance 1..32768 -> distance code 0..29. */
static uint32_t dist_code(uint32_t dist)
{
    uint32_t d = dist - 1u, n;
    if (d < 4u) return d;
    n = floor_log2(d);
    return 2u * n + ((d >> (n - 1u)) & 1u);
}

/* Canonical codes from lengths, bit-reversed. */
static void make_codes(huff_code *h, uint32_t n)
{
    uint16_t count[MAX_BITS + 1u], next[MAX_BITS + 1u];
    uint32_t i, code = 0;
    memset(count, 0, sizeof count);
    for (i = 0; i < n; i++) count[h->len[i]]++;
    count[0] = 0;
    for (i = 1; i <= MAX_BITS; i++) {
        code = (code + count[i - 1u]) << 1;
        next[i] = (uint16_t)code;
    }
    for (i = 0; i < n; i++) {
        uint32_t len = h->len[i], c, r = 0, k;
        if (len == 0) {
            h->code[i] = 0;
            continue;
        }
        c = next[len]++;
        for (k = 0; k < len; k++) r |= ((c >> k) & 1u) << (len - 1u - k);
        h->code[i] = (uint16_t)r;
    }
}

/* Length-limited Huffman code lengths for freq[0..n) (at least two symbols
 * get a code, as the format asks of every code). */
static void build_lengths(deflate_state *s, const uint32_t *freq, uint32_t n, uint32_t limit, huff_code *h)
{
    uint32_t m = 0, i, leaf = 0, next, made, node, total, pos, len;
    for (i = 0; i < n; i++) {
        h->len[i] = 0;
        s->keys[i] = freq[i];
        if (freq[i] > 0) s->idx[m++] = i;
    }
    for (i = 0; m < 2u; i++)
        if (s->keys[i] == 0) {
            s->keys[i] = 1; /* a placeholder: weight 1 for the tree, never sent */
            s->idx[m++] = i;
        }
    if (s->idx[0] > s->idx[1]) { /* a placeholder before a used symbol: symbol order */
        uint32_t t = s->idx[0];
        s->idx[0] = s->idx[1];
        s->idx[1] = t;
    }
    /* ascending by weight, equal weights in symbol order (a stable sort) */
    (void)ls_sort_u32(s->keys, s->idx, m, s->sort_scratch);
    for (i = 0; i < m; i++) s->weight[i] = s->keys[s->idx[i]];
    /* two queues: the sorted leaves [leaf, m) and the internal nodes [next, made) */
    next = m;
    made = m;
    for (i = 0; i + 1u < m; i++) {
        uint32_t pick[2], k;
        for (k = 0; k < 2u; k++) {
            if (leaf < m && (next >= made || s->weight[leaf] <= s->weight[next]))
                pick[k] = leaf++;
            else
                pick[k] = next++;
        }
        s->weight[made] = s->weight[pick[0]] + s->weight[pick[1]];
        s->parent[pick[0]] = (uint16_t)made;
        s->parent[pick[1]] = (uint16_t)made;
        made++;
    }
    /* depths from the root (the last node) down: parents come after children */
    s->depth[made - 1u] = 0;
    for (node = made - 1u; node-- > 0;) s->depth[node] = (uint16_t)(s->depth[s->parent[node]] + 1u);
    memset(s->bl_count, 0, sizeof s->bl_count);
    for (i = 0; i < m; i++) s->bl_count[s->depth[i] > limit ? limit : s->depth[i]]++;
    /* repair the Kraft sum of the clamped lengths: move a code from the
     * limit, split one shorter code in two */
    total = 0;
    for (len = 1; len <= limit; len++) total += (uint32_t)s->bl_count[len] << (limit - len);
    while (total > (1u << limit)) {
        s->bl_count[limit]--;
        for (len = limit - 1u; len > 0; len--)
            if (s->bl_count[len] > 0) {
                s->bl_count[len]--;
                s->bl_count[len + 1u] = (uint16_t)(s->bl_count[len + 1u] + 2u);
                break;
            }
        total--;
    }
    /* the longest codes to the rarest symbols */
    pos = 0;
    for (len = limit; len > 0; len--)
        for (i = 0; i < s->bl_count[len]; i++) h->len[s->idx[pos++]] = (uint8_t)len;
    make_codes(h, n);
}

/* Bits of the block's symbols under the codes lit and dist (extra bits included). */
static uint32_t data_bits(const deflate_state *s, const huff_code *lit, const huff_code *dist)
{
    uint32_t bits = 0, i;
    for (i = 0; i < LL_SYMS; i++) bits += s->lit_freq[i] * lit->len[i];
    for (i = 0; i < 29u; i++) bits += s->lit_freq[257u + i] * ls_deflate_len_extra[i];
    for (i = 0; i < D_SYMS; i++) bits += s->dist_freq[i] * (uint32_t)(dist->len[i] + ls_deflate_dist_extra[i]);
    return bits;
}

static void cl_emit(deflate_state *s, uint32_t sym, uint32_t val)
{
    s->cl_sym[s->ncl] = (uint8_t)sym;
    s->cl_val[s->ncl] = (uint8_t)val;
    s->ncl++;
    s->cl_freq[sym]++;
}

/* Run-length codes the lengths of both codes (RFC 1951 3.2.7). */
static void code_lengths(deflate_state *s, uint32_t hlit, uint32_t hdist)
{
    uint32_t n = hlit + hdist, i = 0;
    s->ncl = 0;
    memset(s->cl_freq, 0, sizeof s->cl_freq);
    while (i < n) {
        uint32_t v = i < hlit ? s->lit.len[i] : s->dist.len[i - hlit], run = 1, left;
        while (i + run < n && (i + run < hlit ? s->lit.len[i + run] : s->dist.len[i + run - hlit]) == v) run++;
        i += run;
        left = run;
        if (v == 0) {
            while (left >= 11u) {
                uint32_t r = left < 138u ? left : 138u;
                cl_emit(s, 18, r - 11u);
                left -= r;
            }
            if (left >= 3u) {
                cl_emit(s, 17, left - 3u);
                left = 0;
            }
        } else {
            cl_emit(s, v, 0);
            left--;
            while (left >= 3u) {
                uint32_t r = left < 6u ? left : 6u;
                cl_emit(s, 16, r - 3u);
                left -= r;
            }
        }
        while (left > 0) {
            cl_emit(s, v, 0);
            left--;
        }
    }
}

static void write_symbols(deflate_state *s, const huff_code *lit, const huff_code *dist)
{
    uint32_t i;
    for (i = 0; i < s->nsyms; i++) {
        uint32_t d = s->sym_dist[i], v = s->sym_ll[i];
        if (d == 0) {
            put_bits(s, lit->code[v], lit->len[v]);
        } else {
            uint32_t lc = length_code(v + 3u), dc = dist_code(d);
            put_bits(s, lit->code[257u + lc], lit->len[257u + lc]);
            if (ls_deflate_len_extra[lc] > 0) put_bits(s, v + 3u - ls_deflate_len_base[lc], ls_deflate_len_extra[lc]);
            put_bits(s, dist->code[dc], dist->len[dc]);
            if (ls_deflate_dist_extra[dc] > 0) put_bits(s, d - ls_deflate_dist_base[dc], ls_deflate_dist_extra[dc]);
        }
    }
    put_bits(s, lit->code[256], lit->len[256]);
}

/* Bits of the block as stored pieces, from the current bit position. */
static uint32_t stored_bits(const deflate_state *s)
{
    uint32_t left = s->block_raw, bits = 0, first = 1;
    while (left > 0) {
        uint32_t m = left < STORED_MAX ? left : STORED_MAX;
        bits += first ? 3u + (8u - (s->nbits + 3u) % 8u) % 8u : 8u;
        bits += 32u + 8u * m;
        left -= m;
        first = 0;
    }
    return bits;
}

static void write_stored(deflate_state *s, uint32_t last)
{
    const unsigned char *p = s->window + s->block_start;
    uint32_t done = 0;
    while (done < s->block_raw) {
        uint32_t m = s->block_raw - done, i, final;
        if (m > STORED_MAX) m = STORED_MAX;
        final = (last && done + m == s->block_raw) ? 1u : 0u;
        put_bits(s, final, 3);
        align_byte(s);
        out_byte(s, m & 0xffu);
        out_byte(s, m >> 8);
        out_byte(s, ~m & 0xffu);
        out_byte(s, (~m >> 8) & 0xffu);
        for (i = 0; i < m; i++) out_byte(s, p[done + i]);
        done += m;
    }
}

/* Writes the symbols gathered since the last block as one block (or stored
 * pieces), the smallest of the three kinds, and starts the next block. */
static void flush_block(deflate_state *s, uint32_t last)
{
    uint32_t hlit = 257, hdist = 1, hclen = 4, i, dyn, fixed, stored;
    s->lit_freq[256] = 1;
    build_lengths(s, s->lit_freq, LL_SYMS, MAX_BITS, &s->lit);
    build_lengths(s, s->dist_freq, D_SYMS, MAX_BITS, &s->dist);
    for (i = 0; i < LL_SYMS; i++)
        if (s->lit.len[i] > 0 && i + 1u > hlit) hlit = i + 1u;
    for (i = 0; i < D_SYMS; i++)
        if (s->dist.len[i] > 0 && i + 1u > hdist) hdist = i + 1u;
    code_lengths(s, hlit, hdist);
    build_lengths(s, s->cl_freq, CL_SYMS, CL_MAX_BITS, &s->cl);
    for (i = 0; i < CL_SYMS; i++)
        if (s->cl.len[ls_deflate_cl_order[i]] > 0 && i + 1u > hclen) hclen = i + 1u;
    dyn = 3u + 14u + 3u * hclen + 2u * s->cl_freq[16] + 3u * s->cl_freq[17] + 7u * s->cl_freq[18];
    for (i = 0; i < CL_SYMS; i++) dyn += s->cl_freq[i] * s->cl.len[i];
    dyn += data_bits(s, &s->lit, &s->dist);
    fixed = 3u + data_bits(s, &s->fixed_lit, &s->fixed_dist);
    stored = s->block_raw > 0 ? stored_bits(s) : 0xffffffffu;
    if (stored < fixed && stored < dyn) {
        write_stored(s, last);
    } else if (fixed <= dyn) {
        put_bits(s, last | (1u << 1), 3);
        write_symbols(s, &s->fixed_lit, &s->fixed_dist);
    } else {
        put_bits(s, last | (2u << 1), 3);
        put_bits(s, hlit - 257u, 5);
        put_bits(s, hdist - 1u, 5);
        put_bits(s, hclen - 4u, 4);
        for (i = 0; i < hclen; i++) put_bits(s, s->cl.len[ls_deflate_cl_order[i]], 3);
        for (i = 0; i < s->ncl; i++) {
            uint32_t c = s->cl_sym[i];
            put_bits(s, s->cl.code[c], s->cl.len[c]);
            if (c == 16u) put_bits(s, s->cl_val[i], 2);
            else if (c == 17u) put_bits(s, s->cl_val[i], 3);
            else if (c == 18u) put_bits(s, s->cl_val[i], 7);
        }
        write_symbols(s, &s->lit, &s->dist);
    }
    s->block_start += s->block_raw;
    s->block_raw = 0;
    s->nsyms = 0;
    memset(s->lit_freq, 0, sizeof s->lit_freq);
    memset(s->dist_freq, 0, sizeof s->dist_freq);
}

/* --- LZ77 ----------------------------------------------------------------- */

static uint32_t hash_at(const deflate_state *s, uint32_t p)
{
    return (((uint32_t)s->window[p] << 10) ^ ((uint32_t)s->window[p + 1u] << 5) ^ s->window[p + 2u]) & HMASK;
}

/* Inserts the string at p; returns the previous head of its chain. */
static uint32_t insert(deflate_state *s, uint32_t p)
{
    uint32_t h = hash_at(s, p), head = s->head[h];
    s->prev[p & WMASK] = (uint16_t)head;
    s->head[h] = (uint16_t)p;
    return head;
}

/* Returns 1 when the symbol buffer is full. */
static int tally(deflate_state *s, uint32_t dist, uint32_t lit_or_len)
{
    s->sym_dist[s->nsyms] = (uint16_t)dist;
    if (dist == 0) {
        s->sym_ll[s->nsyms] = (uint8_t)lit_or_len;
        s->lit_freq[lit_or_len]++;
        s->block_raw++;
    } else {
        s->sym_ll[s->nsyms] = (uint8_t)(lit_or_len - 3u);
        s->lit_freq[257u + length_code(lit_or_len)]++;
        s->dist_freq[dist_code(dist)]++;
        s->block_raw += lit_or_len;
    }
    s->nsyms++;
    return s->nsyms == SYMS;
}

/* The longest match at strstart among the chain from cur (zlib's search:
 * fewer candidates once a good match is in hand, stop at a nice one). */
static uint32_t longest_match(deflate_state *s, uint32_t cur)
{
    const unsigned char *w = s->window, *scan = w + s->strstart;
    uint32_t chain = s->chain, best = s->prev_length, nice = s->nice;
    uint32_t limit = s->strstart > MAX_DIST ? s->strstart - MAX_DIST : 0u;
    uint32_t maxlen = MAX_MATCH;
    if (s->lookahead < maxlen) maxlen = s->lookahead; /* >= MIN_MATCH: the caller checks */
    if (best >= s->good) chain >>= 2;
    if (nice > maxlen) nice = maxlen;
    if (best >= maxlen) return maxlen; /* no longer match fits */
    do {
        const unsigned char *m = w + cur;
        uint32_t len = 0;
        if (m[best] != scan[best] || m[0] != scan[0] || m[1] != scan[1]) continue;
        while (len < maxlen && m[len] == scan[len]) len++;
        if (len > best) {
            s->match_start = cur;
            best = len;
            if (len >= nice) break;
        }
    } while ((cur = s->prev[cur & WMASK]) > limit && --chain != 0);
    return best;
}

/* Lazy matching over the input in the window (zlib's deflate_slow); stops
 * when fewer than MIN_LOOKAHEAD bytes are left, unless finishing. */
static void compress(deflate_state *s, int finish)
{
    for (;;) {
        uint32_t head = 0;
        if (s->lookahead < MIN_LOOKAHEAD && !finish) return;
        if (s->lookahead == 0) break;
        if (s->lookahead >= MIN_MATCH) head = insert(s, s->strstart);
        s->prev_length = s->match_length;
        s->prev_match = s->match_start;
        s->match_length = MIN_MATCH - 1u;
        if (head != 0 && s->prev_length < s->lazy && s->strstart - head <= MAX_DIST) {
            s->match_length = longest_match(s, head);
            if (s->match_length == MIN_MATCH && s->strstart - s->match_start > TOO_FAR)
                s->match_length = MIN_MATCH - 1u;
        }
        if (s->prev_length >= MIN_MATCH && s->match_length <= s->prev_length) {
            uint32_t max_insert = s->strstart + s->lookahead - MIN_MATCH;
            int full = tally(s, s->strstart - 1u - s->prev_match, s->prev_length);
            s->lookahead -= s->prev_length - 1u;
            s->prev_length -= 2u;
            do {
                if (++s->strstart <= max_insert) (void)insert(s, s->strstart);
            } while (--s->prev_length != 0);
            s->match_available = 0;
            s->match_length = MIN_MATCH - 1u;
            s->strstart++;
            if (full) flush_block(s, 0);
        } else if (s->match_available) {
            if (tally(s, 0, s->window[s->strstart - 1u])) flush_block(s, 0);
            s->strstart++;
            s->lookahead--;
        } else {
            s->match_available = 1;
            s->strstart++;
            s->lookahead--;
        }
    }
    if (s->match_available) {
        if (tally(s, 0, s->window[s->strstart - 1u])) flush_block(s, 0);
        s->match_available = 0;
    }
}

/* Moves the upper half of the window down (the block is flushed first if
 * it starts in the lower half). */
static void slide(deflate_state *s)
{
    uint32_t i;
    if (s->block_start < WSIZE) flush_block(s, 0);
    memcpy(s->window, s->window + WSIZE, WSIZE);
    s->strstart -= WSIZE;
    s->block_start -= WSIZE;
    s->match_start = s->match_start >= WSIZE ? s->match_start - WSIZE : 0u;
    s->prev_match = s->prev_match >= WSIZE ? s->prev_match - WSIZE : 0u;
    for (i = 0; i < HSIZE; i++) s->head[i] = (uint16_t)(s->head[i] >= WSIZE ? s->head[i] - WSIZE : 0u);
    for (i = 0; i < WSIZE; i++) s->prev[i] = (uint16_t)(s->prev[i] >= WSIZE ? s->prev[i] - WSIZE : 0u);
}

void ls_deflate_begin_(void *state, uint32_t level, ls_deflate_out_fn out, void *ctx)
{
    deflate_state *s = (deflate_state *)state;
    const uint16_t *p = level_params[(level < 1u ? 1u : level > 9u ? 9u : level) - 1u];
    uint32_t i;
    s->out = out;
    s->ctx = ctx;
    s->good = p[0];
    s->lazy = p[1];
    s->nice = p[2];
    s->chain = p[3];
    s->strstart = s->lookahead = s->block_start = s->block_raw = 0;
    s->match_length = s->prev_length = MIN_MATCH - 1u;
    s->match_start = s->prev_match = s->match_available = 0;
    s->nsyms = s->bitbuf = s->nbits = s->outn = 0;
    memset(s->lit_freq, 0, sizeof s->lit_freq);
    memset(s->dist_freq, 0, sizeof s->dist_freq);
    memset(s->head, 0, sizeof s->head);
    memset(s->prev, 0, sizeof s->prev);
    for (i = 0; i < FIXED_LL; i++) s->fixed_lit.len[i] = (uint8_t)(i < 144u ? 8u : i < 256u ? 9u : i < 280u ? 7u : 8u);
    for (i = 0; i < D_SYMS; i++) s->fixed_dist.len[i] = 5;
    make_codes(&s->fixed_lit, FIXED_LL);
    make_codes(&s->fixed_dist, D_SYMS);
}

void ls_deflate_put_(void *state, const unsigned char *data, size_t n)
{
    deflate_state *s = (deflate_state *)state;
    while (n > 0) {
        uint32_t fill = s->strstart + s->lookahead, m;
        if (fill == 2u * WSIZE) {
            slide(s);
            fill -= WSIZE;
        }
        m = 2u * WSIZE - fill;
        if (m > n) m = (uint32_t)n;
        memcpy(s->window + fill, data, m);
        s->lookahead += m;
        data += m;
        n -= m;
        compress(s, 0);
    }
}

void ls_deflate_end_(void *state)
{
    deflate_state *s = (deflate_state *)state;
    compress(s, 1);
    flush_block(s, 1);
    align_byte(s);
    if (s->outn > 0) s->out(s->ctx, s->outbuf, s->outn);
    s->outn = 0;
}
