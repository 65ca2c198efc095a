/* src/base/math_explog.c - exp, log, log10, pow in double and float.
 *
 * exp: x = k ln2/N + r (N = 64, float 32) with a three-part ln2/N so that the
 * reduction is exact, exp(r) - 1 by a minimax polynomial, times 2^(j/N) from
 * a head+tail table, times 2^(k/N - j/N) by exponent arithmetic (one rounding
 * when the result is subnormal).
 * log: x = 2^k m, m in [1, 2); r = m c_j - 1 computed exactly for a
 * reciprocal c_j with few bits (N = 128 intervals, float 32); the result
 * k ln2 + log(1/c_j) + log1p(r) is summed as a double-double (float-float).
 * pow: the double-double log times y, into exp with the low part folded into
 * the reduced argument; the extra precision keeps the error near 1/2 ulp.
 *
 * Constants, tables and coefficients come from tests/tools/gen_math_coeffs.py.
 */
#include <largesteps/math.h>

#include "math_dd.h"

#define EXP_INVL 0x1.71547652b82fep+6 /* 64/ln2 */
#define EXP_L1 0x1.62e42fefa0000p-7 /* ln2/64, 36-bit head */
#define EXP_L2 0x1.cf79abc9e3b3ap-46
#define EXPF_INVL 0x1.715476p+5f /* 32/ln2 */
#define EXPF_L1 0x1.630000p-6f
#define EXPF_L2 (-0x1.bd0000p-18f)
#define EXPF_L3 (-0x1.05c610p-34f)
#define LN2_HI 0x1.62e42fefa3800p-1
#define LN2_LO 0x1.ef35793c76730p-45
#define LN2F_HI 0x1.62e400p-1f
#define LN2F_LO 0x1.7f7d1cp-20f
#define INVLN10_HI 0x1.bcb7b1526e50ep-2
#define INVLN10_LO 0x1.95355baaafad3p-57
#define INVLN10F_HI 0x1.bcb7b2p-2f
#define INVLN10F_LO (-0x1.5b235ep-27f)

/* EXP_E: degree 4 on [-0.00543637, 0.00543637], weighted error 2^-70.2 */
#define EXP_E0 0x1.0000000000000p-1
#define EXP_E1 0x1.55555555548c7p-3
#define EXP_E2 0x1.55555555590b7p-5
#define EXP_E3 0x1.111123d0386d5p-7
#define EXP_E4 0x1.6c16a18397378p-10
/* EXPF_E: degree 2 on [-0.0108727, 0.0108727], weighted error 2^-42.4 */
#define EXPF_E0 0x1.000000p-1f
#define EXPF_E1 0x1.5555c8p-3f
#define EXPF_E2 0x1.555482p-5f
/* LOG_P: degree 7 on [-0.0078125, 0.0078125], weighted error 2^-69.6 */
#define LOG_P0 0x1.5555555555555p-2
#define LOG_P1 (-0x1.0000000000000p-2)
#define LOG_P2 0x1.9999999999b92p-3
#define LOG_P3 (-0x1.55555555557e0p-3)
#define LOG_P4 0x1.2492490cbfe35p-3
#define LOG_P5 (-0x1.ffffffcb63addp-4)
#define LOG_P6 0x1.c72a9fbc11accp-4
#define LOG_P7 (-0x1.99a7aa1a7d045p-4)
/* LOGF_P: degree 4 on [-0.03125, 0.03125], weighted error 2^-36.6 */
#define LOGF_P0 0x1.555556p-2f
#define LOGF_P1 (-0x1.fffff8p-3f)
#define LOGF_P2 0x1.99998ep-3f
#define LOGF_P3 (-0x1.55b4b2p-3f)
#define LOGF_P4 0x1.24f562p-3f

/* 2^(j/64) as head, tail */
static const double exp_tab[128] = {
    0x1.0000000000000p+0, 0.0,
    0x1.02c9a3e778061p+0, -0x1.19083535b085dp-56,
    0x1.059b0d3158574p+0, 0x1.d73e2a475b465p-55,
    0x1.0874518759bc8p+0, 0x1.186be4bb284ffp-57,
    0x1.0b5586cf9890fp+0, 0x1.8a62e4adc610bp-54,
    0x1.0e3ec32d3d1a2p+0, 0x1.03a1727c57b53p-59,
    0x1.11301d0125b51p+0, -0x1.6c51039449b3ap-54,
    0x1.1429aaea92de0p+0, -0x1.32fbf9af1369ep-54,
    0x1.172b83c7d517bp+0, -0x1.19041b9d78a76p-55,
    0x1.1a35beb6fcb75p+0, 0x1.e5b4c7b4968e4p-55,
    0x1.1d4873168b9aap+0, 0x1.e016e00a2643cp-54,
    0x1.2063b88628cd6p+0, 0x1.dc775814a8495p-55,
    0x1.2387a6e756238p+0, 0x1.9b07eb6c70573p-54,
    0x1.26b4565e27cddp+0, 0x1.2bd339940e9d9p-55,
    0x1.29e9df51fdee1p+0, 0x1.612e8afad1255p-55,
    0x1.2d285a6e4030bp+0, 0x1.0024754db41d5p-54,
    0x1.306fe0a31b715p+0, 0x1.6f46ad23182e4p-55,
    0x1.33c08b26416ffp+0, 0x1.32721843659a6p-54,
    0x1.371a7373aa9cbp+0, -0x1.63aeabf42eae2p-54,
    0x1.3a7db34e59ff7p+0, -0x1.5e436d661f5e3p-56,
    0x1.3dea64c123422p+0, 0x1.ada0911f09ebcp-55,
    0x1.4160a21f72e2ap+0, -0x1.ef3691c309278p-58,
    0x1.44e086061892dp+0, 0x1.89b7a04ef80d0p-59,
    0x1.486a2b5c13cd0p+0, 0x1.3c1a3b69062f0p-56,
    0x1.4bfdad5362a27p+0, 0x1.d4397afec42e2p-56,
    0x1.4f9b2769d2ca7p+0, -0x1.4b309d25957e3p-54,
    0x1.5342b569d4f82p+0, -0x1.07abe1db13cadp-55,
    0x1.56f4736b527dap+0, 0x1.9bb2c011d93adp-54,
    0x1.5ab07dd485429p+0, 0x1.6324c054647adp-54,
    0x1.5e76f15ad2148p+0, 0x1.ba6f93080e65ep-54,
    0x1.6247eb03a5585p+0, -0x1.383c17e40b497p-54,
    0x1.6623882552225p+0, -0x1.bb60987591c34p-54,
    0x1.6a09e667f3bcdp+0, -0x1.bdd3413b26456p-54,
    0x1.6dfb23c651a2fp+0, -0x1.bbe3a683c88abp-57,
    0x1.71f75e8ec5f74p+0, -0x1.16e4786887a99p-55,
    0x1.75feb564267c9p+0, -0x1.0245957316dd3p-54,
    0x1.7a11473eb0187p+0, -0x1.41577ee04992fp-55,
    0x1.7e2f336cf4e62p+0, 0x1.05d02ba15797ep-56,
    0x1.82589994cce13p+0, -0x1.d4c1dd41532d8p-54,
    0x1.868d99b4492edp+0, -0x1.fc6f89bd4f6bap-54,
    0x1.8ace5422aa0dbp+0, 0x1.6e9f156864b27p-54,
    0x1.8f1ae99157736p+0, 0x1.5cc13a2e3976cp-55,
    0x1.93737b0cdc5e5p+0, -0x1.75fc781b57ebcp-57,
    0x1.97d829fde4e50p+0, -0x1.d185b7c1b85d1p-54,
    0x1.9c49182a3f090p+0, 0x1.c7c46b071f2bep-56,
    0x1.a0c667b5de565p+0, -0x1.359495d1cd533p-54,
    0x1.a5503b23e255dp+0, -0x1.d2f6edb8d41e1p-54,
    0x1.a9e6b5579fdbfp+0, 0x1.0fac90ef7fd31p-54,
    0x1.ae89f995ad3adp+0, 0x1.7a1cd345dcc81p-54,
    0x1.b33a2b84f15fbp+0, -0x1.2805e3084d708p-57,
    0x1.b7f76f2fb5e47p+0, -0x1.5584f7e54ac3bp-56,
    0x1.bcc1e904bc1d2p+0, 0x1.23dd07a2d9e84p-55,
    0x1.c199bdd85529cp+0, 0x1.11065895048ddp-55,
    0x1.c67f12e57d14bp+0, 0x1.2884dff483cadp-54,
    0x1.cb720dcef9069p+0, 0x1.503cbd1e949dbp-56,
    0x1.d072d4a07897cp+0, -0x1.cbc3743797a9cp-54,
    0x1.d5818dcfba487p+0, 0x1.2ed02d75b3707p-55,
    0x1.da9e603db3285p+0, 0x1.c2300696db532p-54,
    0x1.dfc97337b9b5fp+0, -0x1.1a5cd4f184b5cp-54,
    0x1.e502ee78b3ff6p+0, 0x1.39e8980a9cc8fp-55,
    0x1.ea4afa2a490dap+0, -0x1.e9c23179c2893p-54,
    0x1.efa1bee615a27p+0, 0x1.dc7f486a4b6b0p-54,
    0x1.f50765b6e4540p+0, 0x1.9d3e12dd8a18bp-54,
    0x1.fa7c1819e90d8p+0, 0x1.74853f3a5931ep-55,
};

/* 2^(j/32) as head, tail */
static const float expf_tab[64] = {
    0x1.000000p+0f, 0.0f,
    0x1.059b0ep+0f, -0x1.9d4f52p-25f,
    0x1.0b5586p+0f, 0x1.9f3122p-25f,
    0x1.11301ep+0f, -0x1.fdb496p-25f,
    0x1.172b84p+0f, -0x1.c15742p-27f,
    0x1.1d4874p+0f, -0x1.d2e8cap-25f,
    0x1.2387a6p+0f, 0x1.ceac48p-25f,
    0x1.29e9e0p+0f, -0x1.5c0424p-25f,
    0x1.306fe0p+0f, 0x1.4636e2p-25f,
    0x1.371a74p+0f, -0x1.18aac6p-25f,
    0x1.3dea64p+0f, 0x1.824684p-25f,
    0x1.44e086p+0f, 0x1.8624b4p-30f,
    0x1.4bfdaep+0f, -0x1.593abcp-25f,
    0x1.5342b6p+0f, -0x1.2c5610p-25f,
    0x1.5ab07ep+0f, -0x1.5bd5ecp-27f,
    0x1.6247ecp+0f, -0x1.f8b550p-25f,
    0x1.6a09e6p+0f, 0x1.9fcef4p-26f,
    0x1.71f75ep+0f, 0x1.1d8beep-25f,
    0x1.7a1148p+0f, -0x1.829fd0p-25f,
    0x1.82589ap+0f, -0x1.accc7cp-26f,
    0x1.8ace54p+0f, 0x1.15506ep-27f,
    0x1.93737cp+0f, -0x1.e64744p-25f,
    0x1.9c4918p+0f, 0x1.51f848p-27f,
    0x1.a5503cp+0f, -0x1.b83b54p-25f,
    0x1.ae89fap+0f, -0x1.a94b14p-26f,
    0x1.b7f770p+0f, -0x1.a09438p-25f,
    0x1.c199bep+0f, -0x1.3d56b2p-27f,
    0x1.cb720ep+0f, -0x1.8837ccp-27f,
    0x1.d5818ep+0f, -0x1.822dbcp-27f,
    0x1.dfc974p+0f, -0x1.908c94p-25f,
    0x1.ea4afap+0f, 0x1.52486cp-27f,
    0x1.f50766p+0f, -0x1.246eb0p-26f,
};

/* c_j, log(1/c_j) head, tail (j >= 53: minus ln2); max |m c - 1| = 2^-7.000 */
static const double log_tab[384] = {
    0x1.0000000000000p+0, 0.0, 0.0,
    0x1.fa00000000000p-1, 0x1.82448a388a2aap-7, 0x1.04b16137f09a0p-62,
    0x1.f600000000000p-1, 0x1.432a925980cc1p-6, -0x1.8cdaf39004192p-60,
    0x1.f200000000000p-1, 0x1.c63d2ec14aaf2p-6, -0x1.ce030a686bd86p-60,
    0x1.ee00000000000p-1, 0x1.252f32f8d183fp-5, -0x1.947f792615916p-59,
    0x1.ea00000000000p-1, 0x1.67c94f2d4bb58p-5, 0x1.0413e6505e603p-59,
    0x1.e800000000000p-1, 0x1.894aa149fb343p-5, 0x1.a8be97660a23dp-60,
    0x1.e400000000000p-1, 0x1.ccb73cdddb2ccp-5, -0x1.e48fb0500efd4p-59,
    0x1.e000000000000p-1, 0x1.08598b59e3a07p-4, -0x1.dd7009902bf32p-58,
    0x1.dc00000000000p-1, 0x1.2aa04a44717a5p-4, -0x1.d15d38d2fa3f7p-58,
    0x1.da00000000000p-1, 0x1.3bdf5a7d1ee64p-4, 0x1.7a976d3b5b45fp-59,
    0x1.d600000000000p-1, 0x1.5e95a4d9791cbp-4, 0x1.f38745c5c450ap-58,
    0x1.d200000000000p-1, 0x1.8197e2f40e3f0p-4, 0x1.b9f2dffbeed43p-60,
    0x1.d000000000000p-1, 0x1.9335e5d594989p-4, -0x1.478a85704ccb7p-58,
    0x1.cc00000000000p-1, 0x1.b6ac88dad5b1cp-4, -0x1.0057eed1ca59fp-59,
    0x1.c800000000000p-1, 0x1.da727638446a2p-4, 0x1.401fa71733019p-58,
    0x1.c600000000000p-1, 0x1.ec739830a1120p-4, -0x1.a2bf991780d3fp-59,
    0x1.c200000000000p-1, 0x1.08598b59e3a07p-3, -0x1.dd7009902bf32p-57,
    0x1.c000000000000p-1, 0x1.1178e8227e47cp-3, -0x1.0e63a5f01c691p-58,
    0x1.bc00000000000p-1, 0x1.23d712a49c202p-3, -0x1.6e38161051d69p-57,
    0x1.ba00000000000p-1, 0x1.2d1610c86813ap-3, -0x1.499a3f25af95fp-58,
    0x1.b600000000000p-1, 0x1.3fb45a59928ccp-3, -0x1.d87e6a354d056p-57,
    0x1.b400000000000p-1, 0x1.4913d8333b561p-3, -0x1.0d5604930f135p-58,
    0x1.b000000000000p-1, 0x1.5bf406b543db2p-3, -0x1.1f5b44c0df7e7p-61,
    0x1.ae00000000000p-1, 0x1.6574ebe8c133ap-3, -0x1.d34f0f4621bedp-60,
    0x1.aa00000000000p-1, 0x1.7898d85444c73p-3, 0x1.ef8f6ebcfb201p-58,
    0x1.a800000000000p-1, 0x1.823c16551a3c2p-3, -0x1.1232ce70be781p-57,
    0x1.a600000000000p-1, 0x1.8beafeb38fe8cp-3, 0x1.55aa8b6997a40p-58,
    0x1.a200000000000p-1, 0x1.9f6c407089664p-3, 0x1.35a19605e67efp-59,
    0x1.a000000000000p-1, 0x1.a93ed3c8ad9e3p-3, 0x1.bcafa9de97203p-57,
    0x1.9e00000000000p-1, 0x1.b31d8575bce3dp-3, -0x1.6353ab386a94dp-57,
    0x1.9a00000000000p-1, 0x1.c6ffbc6f00f71p-3, -0x1.8e58b2c57a4a5p-57,
    0x1.9800000000000p-1, 0x1.d1037f2655e7bp-3, 0x1.60629242471a2p-57,
    0x1.9600000000000p-1, 0x1.db13db0d48940p-3, 0x1.aa11d49f96cb9p-58,
    0x1.9400000000000p-1, 0x1.e530effe71012p-3, 0x1.2276041f43042p-59,
    0x1.9000000000000p-1, 0x1.f991c6cb3b379p-3, 0x1.f665066f980a2p-57,
    0x1.8e00000000000p-1, 0x1.01eae5626c691p-2, -0x1.18290bd2932e2p-59,
    0x1.8c00000000000p-1, 0x1.07138604d5862p-2, 0x1.cdb16ed4e9138p-56,
    0x1.8a00000000000p-1, 0x1.0c42d676162e3p-2, 0x1.162c79d5d11eep-58,
    0x1.8800000000000p-1, 0x1.1178e8227e47cp-2, -0x1.0e63a5f01c691p-57,
    0x1.8400000000000p-1, 0x1.1bf99635a6b95p-2, -0x1.12aeb84249223p-57,
    0x1.8200000000000p-1, 0x1.214456d0eb8d4p-2, 0x1.f7ae91aeba60ap-57,
    0x1.8000000000000p-1, 0x1.269621134db92p-2, 0x1.e0efadd9db02bp-56,
    0x1.7e00000000000p-1, 0x1.2bef07cdc9354p-2, -0x1.82dad7fd86088p-56,
    0x1.7c00000000000p-1, 0x1.314f1e1d35ce4p-2, -0x1.3d69909e5c3dcp-56,
    0x1.7a00000000000p-1, 0x1.36b6776be1117p-2, -0x1.324f0e883858ep-58,
    0x1.7800000000000p-1, 0x1.3c25277333184p-2, -0x1.2ad27e50a8ec6p-56,
    0x1.7600000000000p-1, 0x1.419b423d5e8c7p-2, 0x1.0dbb243827392p-57,
    0x1.7400000000000p-1, 0x1.4718dc271c41bp-2, 0x1.8fb4c14c56eefp-60,
    0x1.7200000000000p-1, 0x1.4c9e09e172c3cp-2, -0x1.123615b147a5dp-58,
    0x1.7000000000000p-1, 0x1.522ae0738a3d8p-2, -0x1.8f7e9b38a6979p-57,
    0x1.6e00000000000p-1, 0x1.57bf753c8d1fbp-2, -0x1.0908d15f88b63p-57,
    0x1.6c00000000000p-1, 0x1.5d5bddf595f30p-2, -0x1.6541148cbb8a2p-56,
    0x1.6a00000000000p-1, -0x1.62c82f2b9c795p-2, -0x1.7b7af915300e5p-57,
    0x1.6800000000000p-1, -0x1.5d1bdbf5809cap-2, -0x1.4236383dc7fe1p-56,
    0x1.6600000000000p-1, -0x1.5767717455a6cp-2, -0x1.526adb283660cp-56,
    0x1.6400000000000p-1, -0x1.51aad872df82dp-2, -0x1.3927ac19f55e3p-59,
    0x1.6200000000000p-1, -0x1.4be5f957778a1p-2, 0x1.259b35b04813dp-57,
    0x1.6000000000000p-1, -0x1.4618bc21c5ec2p-2, -0x1.f42decdeccf1dp-56,
    0x1.5e00000000000p-1, -0x1.404308686a7e4p-2, 0x1.0bcfb6082ce6dp-56,
    0x1.5c00000000000p-1, -0x1.3a64c556945eap-2, 0x1.c68651945f97cp-57,
    0x1.5a00000000000p-1, -0x1.347dd9a987d55p-2, 0x1.4dd4c580919f8p-57,
    0x1.5800000000000p-1, -0x1.2e8e2bae11d31p-2, 0x1.8f4cdb95ebdf9p-56,
    0x1.5600000000000p-1, -0x1.2895a13de86a3p-2, -0x1.7ad24c13f040ep-56,
    0x1.5400000000000p-1, -0x1.22941fbcf7966p-2, 0x1.76f5eb09628afp-56,
    0x1.5200000000000p-1, -0x1.1c898c16999fbp-2, 0x1.0e5c62aff1c44p-60,
    0x1.5000000000000p-1, -0x1.1675cababa60ep-2, -0x1.ce63eab883717p-61,
    0x1.5000000000000p-1, -0x1.1675cababa60ep-2, -0x1.ce63eab883717p-61,
    0x1.4e00000000000p-1, -0x1.1058bf9ae4ad5p-2, -0x1.89fa0ab4cb31dp-58,
    0x1.4c00000000000p-1, -0x1.0a324e27390e3p-2, -0x1.7dcfde8061c03p-56,
    0x1.4a00000000000p-1, -0x1.0402594b4d041p-2, 0x1.28ec217a5022dp-57,
    0x1.4800000000000p-1, -0x1.fb9186d5e3e2bp-3, 0x1.caaae64f21acbp-57,
    0x1.4600000000000p-1, -0x1.ef0adcbdc5936p-3, -0x1.48637950dc20dp-57,
    0x1.4600000000000p-1, -0x1.ef0adcbdc5936p-3, -0x1.48637950dc20dp-57,
    0x1.4400000000000p-1, -0x1.e27076e2af2e6p-3, 0x1.61578001e0162p-59,
    0x1.4200000000000p-1, -0x1.d5c216b4fbb91p-3, -0x1.6e443597e4d40p-57,
    0x1.4000000000000p-1, -0x1.c8ff7c79a9a22p-3, 0x1.4f689f8434012p-57,
    0x1.3e00000000000p-1, -0x1.bc286742d8cd6p-3, -0x1.4fce744870f55p-58,
    0x1.3e00000000000p-1, -0x1.bc286742d8cd6p-3, -0x1.4fce744870f55p-58,
    0x1.3c00000000000p-1, -0x1.af3c94e80bff3p-3, 0x1.398cff3641985p-58,
    0x1.3a00000000000p-1, -0x1.a23bc1fe2b563p-3, -0x1.93711b07a998cp-59,
    0x1.3800000000000p-1, -0x1.9525a9cf456b4p-3, -0x1.d904c1d4e2e26p-57,
    0x1.3800000000000p-1, -0x1.9525a9cf456b4p-3, -0x1.d904c1d4e2e26p-57,
    0x1.3600000000000p-1, -0x1.87fa06520c911p-3, 0x1.bf7fdbfa08d9ap-57,
    0x1.3400000000000p-1, -0x1.7ab890210d909p-3, -0x1.be36b2d6a0608p-59,
    0x1.3200000000000p-1, -0x1.6d60fe719d21dp-3, 0x1.caae268ecd179p-57,
    0x1.3200000000000p-1, -0x1.6d60fe719d21dp-3, 0x1.caae268ecd179p-57,
    0x1.3000000000000p-1, -0x1.5ff3070a793d4p-3, 0x1.bc60efafc6f6ep-58,
    0x1.2e00000000000p-1, -0x1.526e5e3a1b438p-3, 0x1.746ff8a470d3ap-57,
    0x1.2e00000000000p-1, -0x1.526e5e3a1b438p-3, 0x1.746ff8a470d3ap-57,
    0x1.2c00000000000p-1, -0x1.44d2b6ccb7d1ep-3, -0x1.9f4f6543e1f88p-57,
    0x1.2a00000000000p-1, -0x1.371fc201e8f74p-3, -0x1.de6cb62af18a0p-58,
    0x1.2a00000000000p-1, -0x1.371fc201e8f74p-3, -0x1.de6cb62af18a0p-58,
    0x1.2800000000000p-1, -0x1.29552f81ff523p-3, -0x1.301771c407dbfp-57,
    0x1.2600000000000p-1, -0x1.1b72ad52f67a0p-3, -0x1.483023472cd74p-58,
    0x1.2600000000000p-1, -0x1.1b72ad52f67a0p-3, -0x1.483023472cd74p-58,
    0x1.2400000000000p-1, -0x1.0d77e7cd08e59p-3, -0x1.9a5dc5e9030acp-57,
    0x1.2200000000000p-1, -0x1.fec9131dbeabbp-4, 0x1.5746b9981b36cp-58,
    0x1.2200000000000p-1, -0x1.fec9131dbeabbp-4, 0x1.5746b9981b36cp-58,
    0x1.2000000000000p-1, -0x1.e27076e2af2e6p-4, 0x1.61578001e0162p-60,
    0x1.1e00000000000p-1, -0x1.c5e548f5bc743p-4, -0x1.5d617ef8161b1p-60,
    0x1.1e00000000000p-1, -0x1.c5e548f5bc743p-4, -0x1.5d617ef8161b1p-60,
    0x1.1c00000000000p-1, -0x1.a926d3a4ad563p-4, -0x1.942f48aa70ea9p-58,
    0x1.1c00000000000p-1, -0x1.a926d3a4ad563p-4, -0x1.942f48aa70ea9p-58,
    0x1.1a00000000000p-1, -0x1.8c345d6319b21p-4, 0x1.4a697ab3424a9p-61,
    0x1.1800000000000p-1, -0x1.6f0d28ae56b4cp-4, 0x1.906d99184b992p-58,
    0x1.1800000000000p-1, -0x1.6f0d28ae56b4cp-4, 0x1.906d99184b992p-58,
    0x1.1600000000000p-1, -0x1.51b073f06183fp-4, -0x1.a49e39a1a8be4p-58,
    0x1.1600000000000p-1, -0x1.51b073f06183fp-4, -0x1.a49e39a1a8be4p-58,
    0x1.1400000000000p-1, -0x1.341d7961bd1d1p-4, 0x1.b599f227becbbp-58,
    0x1.1200000000000p-1, -0x1.16536eea37ae1p-4, 0x1.79da3e8c22cdap-60,
    0x1.1200000000000p-1, -0x1.16536eea37ae1p-4, 0x1.79da3e8c22cdap-60,
    0x1.1000000000000p-1, -0x1.f0a30c01162a6p-5, -0x1.85f325c5bbacdp-59,
    0x1.1000000000000p-1, -0x1.f0a30c01162a6p-5, -0x1.85f325c5bbacdp-59,
    0x1.0e00000000000p-1, -0x1.b42dd711971bfp-5, 0x1.eb9759c130499p-60,
    0x1.0e00000000000p-1, -0x1.b42dd711971bfp-5, 0x1.eb9759c130499p-60,
    0x1.0c00000000000p-1, -0x1.77458f632dcfcp-5, -0x1.18d3ca87b9296p-59,
    0x1.0a00000000000p-1, -0x1.39e87b9febd60p-5, 0x1.5bfa937f551bbp-59,
    0x1.0a00000000000p-1, -0x1.39e87b9febd60p-5, 0x1.5bfa937f551bbp-59,
    0x1.0800000000000p-1, -0x1.f829b0e783300p-6, -0x1.33e3f04f1ef23p-60,
    0x1.0800000000000p-1, -0x1.f829b0e783300p-6, -0x1.33e3f04f1ef23p-60,
    0x1.0600000000000p-1, -0x1.7b91b07d5b11bp-6, 0x1.5b602ace3a510p-60,
    0x1.0600000000000p-1, -0x1.7b91b07d5b11bp-6, 0x1.5b602ace3a510p-60,
    0x1.0400000000000p-1, -0x1.fc0a8b0fc03e4p-7, 0x1.83092c59642a1p-62,
    0x1.0400000000000p-1, -0x1.fc0a8b0fc03e4p-7, 0x1.83092c59642a1p-62,
    0x1.0200000000000p-1, -0x1.fe02a6b106789p-8, 0x1.e44b7e3711ebfp-67,
    0x1.0200000000000p-1, -0x1.fe02a6b106789p-8, 0x1.e44b7e3711ebfp-67,
    0x1.0000000000000p-1, 0.0, 0.0,
};

/* c_j, log(1/c_j) head, tail (j >= 13: minus ln2); max |m c - 1| = 2^-5.000 */
static const float logf_tab[96] = {
    0x1.000000p+0f, 0.0f, 0.0f,
    0x1.e80000p-1f, 0x1.894aa2p-5f, -0x1.6c0998p-30f,
    0x1.d80000p-1f, 0x1.4d3116p-4f, -0x1.6fc0aap-31f,
    0x1.d00000p-1f, 0x1.9335e6p-4f, -0x1.535b3cp-31f,
    0x1.c00000p-1f, 0x1.1178e8p-3f, 0x1.13f23ep-30f,
    0x1.b80000p-1f, 0x1.365fccp-3f, -0x1.fd4dfep-28f,
    0x1.a80000p-1f, 0x1.823c16p-3f, 0x1.5468f0p-29f,
    0x1.a00000p-1f, 0x1.a93ed4p-3f, -0x1.ba930ep-30f,
    0x1.980000p-1f, 0x1.d10380p-3f, -0x1.b35430p-28f,
    0x1.880000p-1f, 0x1.1178e8p-2f, 0x1.13f23ep-29f,
    0x1.800000p-1f, 0x1.269622p-2f, -0x1.d9648ep-27f,
    0x1.780000p-1f, 0x1.3c2528p-2f, -0x1.1999d0p-27f,
    0x1.700000p-1f, 0x1.522ae0p-2f, 0x1.ce28f6p-28f,
    0x1.680000p-1f, -0x1.5d1bdcp-2f, 0x1.4fec6cp-31f,
    0x1.600000p-1f, -0x1.4618bcp-2f, -0x1.0e2f62p-29f,
    0x1.580000p-1f, -0x1.2e8e2cp-2f, 0x1.47b8b4p-28f,
    0x1.500000p-1f, -0x1.1675cap-2f, -0x1.7574c2p-27f,
    0x1.480000p-1f, -0x1.fb9186p-3f, -0x1.abc7c6p-28f,
    0x1.480000p-1f, -0x1.fb9186p-3f, -0x1.abc7c6p-28f,
    0x1.400000p-1f, -0x1.c8ff7cp-3f, -0x1.e6a688p-29f,
    0x1.380000p-1f, -0x1.9525aap-3f, 0x1.85d4a6p-30f,
    0x1.300000p-1f, -0x1.5ff308p-3f, 0x1.eb0d86p-28f,
    0x1.300000p-1f, -0x1.5ff308p-3f, 0x1.eb0d86p-28f,
    0x1.280000p-1f, -0x1.295530p-3f, 0x1.f802b8p-29f,
    0x1.200000p-1f, -0x1.e27076p-4f, -0x1.c55e5cp-29f,
    0x1.200000p-1f, -0x1.e27076p-4f, -0x1.c55e5cp-29f,
    0x1.180000p-1f, -0x1.6f0d28p-4f, -0x1.5cad6ap-29f,
    0x1.100000p-1f, -0x1.f0a30cp-5f, -0x1.162a66p-37f,
    0x1.100000p-1f, -0x1.f0a30cp-5f, -0x1.162a66p-37f,
    0x1.080000p-1f, -0x1.f829b0p-6f, -0x1.cf0660p-31f,
    0x1.080000p-1f, -0x1.f829b0p-6f, -0x1.cf0660p-31f,
    0x1.000000p-1f, 0.0f, 0.0f,
};

/* ------------------------------------------------------------------ */
/* double                                                               */

/* exp(x + xl) for -745.2 <= x <= 710, |xl| <= 2^-40 |x|. */
static double exp_core(double x, double xl)
{
    double kf = (x * EXP_INVL + 0x1.8p52) - 0x1.8p52; /* round to nearest integer */
    int32_t k = (int32_t)kf;
    int32_t j = (int32_t)((uint32_t)k & 63u);
    int32_t e = (k - j) / 64;
    double hi = x - kf * EXP_L1; /* exact */
    double lo = kf * EXP_L2;
    double r = hi - lo;
    double dr = ((hi - r) - lo) + xl;
    double p = r + r * r * (EXP_E0 + r * (EXP_E1 + r * (EXP_E2 + r * (EXP_E3 + r * EXP_E4))));
    double th = exp_tab[2 * (size_t)j], tl = exp_tab[2 * (size_t)j + 1];
    /* exp(r + dr) = (1 + p)(1 + dr): dr carries pow's low part, up to 2^-44 */
    double y = th + (tl + th * (p + (dr + dr * p)));
    if (e >= -1021) {
        if (e <= 1023) return y * md_pow2(e);
        return (y * 2.0) * md_pow2(e - 1);
    }
    return (y * md_pow2(e + 1000)) * 0x1p-1000; /* one rounding into subnormals */
}

double ls_exp(double x)
{
    uint64_t ax = md_bits(x) & LS_D_ABS;
    if (ax > LS_D_INF) return md_nan();
    if (x > 710.0) return md_inf();
    if (x < -745.2) return 0.0;
    if (ax < 0x3c90000000000000ull) return 1.0 + x; /* |x| < 2^-54 */
    return exp_core(x, 0.0);
}

/* log(x) = *hi + *lo (|lo| <= 2^-52 |hi|, error about 2^-70 relative) for
 * finite x > 0, including subnormals. */
static void log_core(double x, double *hi, double *lo)
{
    uint64_t u = md_bits(x);
    int32_t k = 0;
    uint32_t j;
    const double *t;
    double m, mh, ml, c, a, b, rh, rl, zh, zl, p, kf, s1, e1, s2, e2, s3, e3;
    if (u < 0x0010000000000000ull) { /* subnormal */
        u = md_bits(x * 0x1p54);
        k = -54;
    }
    k += (int32_t)(u >> 52) - 1023;
    j = (uint32_t)(u >> 45) & 127u;
    m = md_from((u & 0x000fffffffffffffull) | 0x3ff0000000000000ull);
    t = &log_tab[3 * (size_t)j];
    c = t[0];
    if (j >= 53u) k += 1; /* table holds log(1/c) - ln2 */
    /* r = m c - 1 exactly: c has 8 bits, m = mh + ml with 26 + 27 bits */
    mh = md_from(md_bits(m) & 0xfffffffff8000000ull);
    ml = m - mh;
    a = c * mh - 1.0;
    b = c * ml;
    md_two_sum(a, b, &rh, &rl);
    /* log1p(r) = r - r^2/2 + r^3 P(r) */
    md_two_prod(rh, rh, &zh, &zl);
    p = LOG_P0 + rh * (LOG_P1 + rh * (LOG_P2 + rh * (LOG_P3 + rh * (LOG_P4 + rh * (LOG_P5 + rh * (LOG_P6 + rh * LOG_P7))))));
    kf = (double)k;
    md_two_sum(kf * LN2_HI, t[1], &s1, &e1); /* kf * LN2_HI is exact */
    md_two_sum(s1, rh, &s2, &e2);
    md_two_sum(s2, -0.5 * zh, &s3, &e3);
    e1 = (e1 + e2 + e3) + (kf * LN2_LO + t[2] + rl - 0.5 * zl - rh * rl + zh * rh * p);
    md_fast_two_sum(s3, e1, hi, lo);
}

double ls_log(double x)
{
    uint64_t u = md_bits(x);
    double h, l;
    if (u >= LS_D_INF) { /* negative (incl. -0), +Inf, NaN */
        if (u == LS_D_INF) return x;
        if (u == 0x8000000000000000ull) return -md_inf();
        return md_nan();
    }
    if (u == 0u) return -md_inf();
    log_core(x, &h, &l);
    return h;
}

double ls_log10(double x)
{
    uint64_t u = md_bits(x);
    double h, l, p, e;
    if (u >= LS_D_INF) {
        if (u == LS_D_INF) return x;
        if (u == 0x8000000000000000ull) return -md_inf();
        return md_nan();
    }
    if (u == 0u) return -md_inf();
    log_core(x, &h, &l);
    md_two_prod(h, INVLN10_HI, &p, &e);
    e += h * INVLN10_LO + l * INVLN10_HI;
    return p + e;
}

/* 0: y not an integer, 1: odd integer, 2: even integer. y finite, nonzero. */
static int32_t int_kind(double y)
{
    uint64_t u = md_bits(y) & LS_D_ABS;
    int32_t ex = (int32_t)(u >> 52) - 1023;
    uint64_t frac;
    if (ex >= 53) return 2;
    if (ex < 0) return 0;
    frac = (u & 0x000fffffffffffffull) | 0x0010000000000000ull;
    if ((frac & ((1ull << (52 - ex)) - 1u)) != 0u) return 0; /* ex = 52: mask 0 */
    return ((frac >> (52 - ex)) & 1u) ? 1 : 2;
}

double ls_pow(double x, double y)
{
    uint64_t ux = md_bits(x), uy = md_bits(y);
    uint64_t ax = ux & LS_D_ABS, ay = uy & LS_D_ABS;
    int32_t neg = 0, yk;
    double h, l, zh, zl, r;
    if (ay == 0u || ux == 0x3ff0000000000000ull) return 1.0; /* pow(x, +-0), pow(1, y) */
    if (ax > LS_D_INF || ay > LS_D_INF) return md_nan();
    if (ay == LS_D_INF) {
        if (ax == 0x3ff0000000000000ull) return 1.0; /* pow(-1, +-Inf) */
        return ((ax < 0x3ff0000000000000ull) == (uy >> 63 != 0u)) ? md_inf() : 0.0;
    }
    yk = int_kind(y);
    if (ux >> 63) {
        if (yk == 0 && ax != 0u && ax != LS_D_INF) return md_nan(); /* x < 0, y not integer */
        neg = (yk == 1);
    }
    if (ax == 0u || ax == LS_D_INF) {
        /* |x| = 0 and y < 0, or |x| = Inf and y > 0: Inf; otherwise 0 */
        r = ((ax == 0u) == (uy >> 63 != 0u)) ? md_inf() : 0.0;
        return neg ? -r : r;
    }
    if (ax == 0x3ff0000000000000ull) return neg ? -1.0 : 1.0; /* x = -1 */
    if (ay >= 0x43f0000000000000ull) { /* |y| >= 2^64: |y log x| > 2^11 */
        return ((ax > 0x3ff0000000000000ull) == (uy >> 63 == 0u)) ? md_inf() : 0.0;
    }
    log_core(md_from(ax), &h, &l);
    md_two_prod(y, h, &zh, &zl);
    zl += y * l;
    md_fast_two_sum(zh, zl, &zh, &zl);
    if (zh > 710.0) r = md_inf();
    else if (zh < -745.2) r = 0.0;
    else r = exp_core(zh, zl);
    return neg ? -r : r;
}

/* ------------------------------------------------------------------ */
/* float (float arithmetic only)                                        */

/* exp(x + xl) for -104 <= x <= 89. */
static float expf_core(float x, float xl)
{
    float kf = (x * EXPF_INVL + 0x1.8p23f) - 0x1.8p23f;
    int32_t k = (int32_t)kf;
    int32_t j = (int32_t)((uint32_t)k & 31u);
    int32_t e = (k - j) / 32;
    float hi = x - kf * EXPF_L1; /* exact */
    float r1, e1, lo, r, dr, p, th, tl, y;
    mf_two_sum(hi, -(kf * EXPF_L2), &r1, &e1); /* kf * EXPF_L2 is exact */
    lo = (e1 - kf * EXPF_L3) + xl;
    mf_fast_two_sum(r1, lo, &r, &dr);
    p = r + r * r * (EXPF_E0 + r * (EXPF_E1 + r * EXPF_E2));
    th = expf_tab[2 * (size_t)j];
    tl = expf_tab[2 * (size_t)j + 1];
    y = th + (tl + th * (p + (dr + dr * p)));
    if (e >= -125) {
        if (e <= 127) return y * mf_pow2(e);
        return (y * 2.0f) * mf_pow2(e - 1);
    }
    return (y * mf_pow2(e + 100)) * 0x1p-100f;
}

float ls_expf(float x)
{
    uint32_t ax = mf_bits(x) & LS_F_ABS;
    if (ax > LS_F_INF) return mf_nan();
    if (x > 89.0f) return mf_inf();
    if (x < -104.0f) return 0.0f;
    if (ax < 0x33000000u) return 1.0f + x; /* |x| < 2^-25 */
    return expf_core(x, 0.0f);
}

static void logf_core(float x, float *hi, float *lo)
{
    uint32_t u = mf_bits(x);
    int32_t k = 0;
    uint32_t j;
    const float *t;
    float m, mh, ml, c, a, b, rh, rl, zh, zl, p, kf, s1, e1, s2, e2, s3, e3;
    if (u < 0x00800000u) {
        u = mf_bits(x * 0x1p25f);
        k = -25;
    }
    k += (int32_t)(u >> 23) - 127;
    j = (u >> 18) & 31u;
    m = mf_from((u & 0x007fffffu) | 0x3f800000u);
    t = &logf_tab[3 * (size_t)j];
    c = t[0];
    if (j >= 13u) k += 1;
    /* c has 6 bits, m = mh + ml with 12 + 12 bits */
    mh = mf_from(mf_bits(m) & 0xfffff000u);
    ml = m - mh;
    a = c * mh - 1.0f;
    b = c * ml;
    mf_two_sum(a, b, &rh, &rl);
    mf_two_prod(rh, rh, &zh, &zl);
    p = LOGF_P0 + rh * (LOGF_P1 + rh * (LOGF_P2 + rh * (LOGF_P3 + rh * LOGF_P4)));
    kf = (float)k;
    mf_two_sum(kf * LN2F_HI, t[1], &s1, &e1);
    mf_two_sum(s1, rh, &s2, &e2);
    mf_two_sum(s2, -0.5f * zh, &s3, &e3);
    e1 = (e1 + e2 + e3) + (kf * LN2F_LO + t[2] + rl - 0.5f * zl - rh * rl + zh * rh * p);
    mf_fast_two_sum(s3, e1, hi, lo);
}

float ls_logf(float x)
{
    uint32_t u = mf_bits(x);
    float h, l;
    if (u >= LS_F_INF) {
        if (u == LS_F_INF) return x;
        if (u == 0x80000000u) return -mf_inf();
        return mf_nan();
    }
    if (u == 0u) return -mf_inf();
    logf_core(x, &h, &l);
    return h;
}

float ls_log10f(float x)
{
    uint32_t u = mf_bits(x);
    float h, l, p, e;
    if (u >= LS_F_INF) {
        if (u == LS_F_INF) return x;
        if (u == 0x80000000u) return -mf_inf();
        return mf_nan();
    }
    if (u == 0u) return -mf_inf();
    logf_core(x, &h, &l);
    mf_two_prod(h, INVLN10F_HI, &p, &e);
    e += h * INVLN10F_LO + l * INVLN10F_HI;
    return p + e;
}

static int32_t int_kindf(float y)
{
    uint32_t u = mf_bits(y) & LS_F_ABS;
    int32_t ex = (int32_t)(u >> 23) - 127;
    uint32_t frac;
    if (ex >= 24) return 2;
    if (ex < 0) return 0;
    frac = (u & 0x007fffffu) | 0x00800000u;
    if ((frac & ((1u << (23 - ex)) - 1u)) != 0u) return 0;
    return ((frac >> (23 - ex)) & 1u) ? 1 : 2;
}

float ls_powf(float x, float y)
{
    uint32_t ux = mf_bits(x), uy = mf_bits(y);
    uint32_t ax = ux & LS_F_ABS, ay = uy & LS_F_ABS;
    int32_t neg = 0, yk;
    float h, l, zh, zl, r;
    if (ay == 0u || ux == 0x3f800000u) return 1.0f;
    if (ax > LS_F_INF || ay > LS_F_INF) return mf_nan();
    if (ay == LS_F_INF) {
        if (ax == 0x3f800000u) return 1.0f;
        return ((ax < 0x3f800000u) == (uy >> 31 != 0u)) ? mf_inf() : 0.0f;
    }
    yk = int_kindf(y);
    if (ux >> 31) {
        if (yk == 0 && ax != 0u && ax != LS_F_INF) return mf_nan();
        neg = (yk == 1);
    }
    if (ax == 0u || ax == LS_F_INF) {
        r = ((ax == 0u) == (uy >> 31 != 0u)) ? mf_inf() : 0.0f;
        return neg ? -r : r;
    }
    if (ax == 0x3f800000u) return neg ? -1.0f : 1.0f;
    if (ay >= 0x53800000u) { /* |y| >= 2^40: |y log x| > 2^15 */
        return ((ax > 0x3f800000u) == (uy >> 31 == 0u)) ? mf_inf() : 0.0f;
    }
    logf_core(mf_from(ax), &h, &l);
    mf_two_prod(y, h, &zh, &zl);
    zl += y * l;
    mf_fast_two_sum(zh, zl, &zh, &zl);
    if (zh > 89.0f) r = mf_inf();
    else if (zh < -104.0f) r = 0.0f;
    else r = expf_core(zh, zl);
    return neg ? -r : r;
}
