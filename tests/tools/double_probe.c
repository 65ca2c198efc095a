/* double_probe.c - planted double arithmetic in float code, for
 * tests/tools/no_double.sh to catch: a float scaled by a double constant
 * (an unsuffixed 0.5) and a float widened for sqrt. */
#include <math.h>
float probe_scale(float x);
float probe_scale(float x)
{
    return (float)(x * 0.5 + sqrt(x));
}
