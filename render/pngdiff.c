/* pngdiff - compares two PNG images by decoded pixels.
   usage: pngdiff A.png B.png [--threshold 16] [--max-bad 32] [--diff out.png]
   A pixel is bad when its largest RGB channel difference exceeds the threshold; the
   comparison fails when more than max-bad pixels are bad, or the sizes differ.
   Exit status: 0 pass, 1 fail, 2 usage or read error. */
#include "rj_render.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int usage(void)
{
    fprintf(stderr, "usage: pngdiff A.png B.png [--threshold 16] [--max-bad 32] [--diff out.png]\n");
    return 2;
}

static int parse_int(const char *s, long *v)
{
    char *end;
    *v = strtol(s, &end, 10);
    return *s && !*end && *v >= 0;
}

int main(int argc, char **argv)
{
    const char *pa = NULL, *pb = NULL, *pd = NULL;
    long thr = 16, maxbad = 32;
    unsigned char *a = NULL, *b = NULL;
    int wa, ha, wb, hb, i, fail;
    char err[512];
    rjr_diff d;

    for (i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--threshold") && i + 1 < argc) { if (!parse_int(argv[++i], &thr) || thr > 255) return usage(); }
        else if (!strcmp(argv[i], "--max-bad") && i + 1 < argc) { if (!parse_int(argv[++i], &maxbad)) return usage(); }
        else if (!strcmp(argv[i], "--diff") && i + 1 < argc) pd = argv[++i];
        else if (argv[i][0] == '-' && argv[i][1]) return usage();
        else if (!pa) pa = argv[i];
        else if (!pb) pb = argv[i];
        else return usage();
    }
    if (!pa || !pb) return usage();
    if (rjr_load_png(pa, &a, &wa, &ha, err, sizeof err) != 0) { fprintf(stderr, "pngdiff: %s\n", err); return 2; }
    if (rjr_load_png(pb, &b, &wb, &hb, err, sizeof err) != 0) { fprintf(stderr, "pngdiff: %s\n", err); free(a); return 2; }
    if (wa != wb || ha != hb) {
        printf("size mismatch: %dx%d vs %dx%d\nFAIL\n", wa, ha, wb, hb);
        free(a); free(b);
        return 1;
    }
    rjr_compare(a, b, wa, ha, (int)thr, &d);
    fail = d.bad_pixels > maxbad;
    if (isinf(d.psnr)) printf("max delta %d, bad pixels %ld (delta > %ld, allowed %ld), PSNR inf dB\n", d.max_delta, d.bad_pixels, thr, maxbad);
    else printf("max delta %d, bad pixels %ld (delta > %ld, allowed %ld), PSNR %.2f dB\n", d.max_delta, d.bad_pixels, thr, maxbad, d.psnr);
    if (pd && rjr_write_diff_png(pd, a, b, wa, ha, (int)thr, err, sizeof err) != 0) {
        fprintf(stderr, "pngdiff: %s\n", err);
        free(a); free(b);
        return 2;
    }
    printf("%s\n", fail ? "FAIL" : "PASS");
    free(a);
    free(b);
    return fail ? 1 : 0;
}
