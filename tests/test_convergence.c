/*
 * Grid-convergence analysis against the worked examples of Celik et al.
 * (2008), Table 1, and on synthetic sequences with known order.
 */
#include <criterion/criterion.h>
#include <math.h>

#include "campaign/convergence.h"

/* 2-D grids given as cell counts: h = (1/N)^(1/2) */
static void three(const double N[3], const double phi[3], struct conv_result *r)
{
    double h[3];
    for (int k = 0; k < 3; k++)
        h[k] = conv_h_from_cells(N[k], 2, 1.0);
    struct err e = {0};
    cr_assert_eq(conv_three_grid(h, phi, 1.25, r, &e), 0, "%s", e.msg);
}

Test(convergence, celik_table1_case1)
{
    struct conv_result r;
    three((double[]){18000, 8000, 4500}, (double[]){6.063, 5.972, 5.863}, &r);
    cr_assert_eq(r.kind, CONV_MONOTONE);
    cr_assert_lt(fabs(r.p - 1.53397), 1e-5, "p = %.7f", r.p);
    cr_assert_lt(fabs(r.phi_ext - 6.16850), 1e-5, "phi_ext = %.7f", r.phi_ext);
    cr_assert_lt(fabs(100 * r.gci_fine - 2.1750), 1e-4, "GCI_fine = %.5f %%", 100 * r.gci_fine);
    cr_assert_lt(fabs(100 * r.e_a21 - 1.5009), 1e-4);
}

Test(convergence, celik_table1_case3_oscillatory)
{
    struct conv_result r;
    three((double[]){18000, 4500, 980}, (double[]){6.0042, 5.9624, 6.0909}, &r);
    cr_assert_eq(r.kind, CONV_OSCILLATORY);
    cr_assert_lt(fabs(r.p - 1.50769), 1e-5, "p = %.7f", r.p);
}

/* phi(h) = phi0 + C h^p recovers p exactly, for ratios 2 and 1.5 */
Test(convergence, exact_orders_on_synthetic_sequences)
{
    const double orders[2] = {1.0, 2.0}, ratios[2] = {2.0, 1.5};
    for (int a = 0; a < 2; a++)
        for (int b = 0; b < 2; b++) {
            double h[3] = {0.1, 0.1 * ratios[b], 0.1 * ratios[b] * ratios[b]}, phi[3];
            for (int k = 0; k < 3; k++)
                phi[k] = 3.0 + 0.7 * pow(h[k], orders[a]);
            struct conv_result r;
            struct err e = {0};
            cr_assert_eq(conv_three_grid(h, phi, 1.25, &r, &e), 0, "%s", e.msg);
            cr_assert_eq(r.kind, CONV_MONOTONE);
            cr_assert_lt(fabs(r.p - orders[a]), 1e-9, "p = %.12f for order %g ratio %g", r.p,
                         orders[a], ratios[b]);
            cr_assert_lt(fabs(r.phi_ext - 3.0), 1e-9);
            /* in the asymptotic range the ratio is phi1/phi2 (GCIs are relative
             * to different solutions), i.e. 1 up to the solution change */
            cr_assert_lt(fabs(r.asymptotic - r.phi[0] / r.phi[1]), 1e-9, "%g", r.asymptotic);
        }
    /* unequal ratios need the fixed-point iteration */
    double h[3] = {1.0, 1.5, 3.0}, phi[3];
    for (int k = 0; k < 3; k++)
        phi[k] = 1.0 + pow(h[k], 1.7);
    struct conv_result r;
    struct err e = {0};
    cr_assert_eq(conv_three_grid(h, phi, 1.25, &r, &e), 0);
    cr_assert_lt(fabs(r.p - 1.7), 1e-9, "p = %.12f", r.p);
    cr_assert_gt(r.iterations, 1);
}

Test(convergence, divergent_and_degenerate_sequences_flagged)
{
    double h[3] = {1, 2, 4};
    struct conv_result r;
    struct err e = {0};
    /* differences grow as the grid is refined */
    cr_assert_eq(conv_three_grid(h, (double[]){1.0, 1.5, 1.6}, 1.25, &r, &e), 0);
    cr_assert_eq(r.kind, CONV_DIVERGENT);
    cr_assert(isnan(r.gci_fine) && isnan(r.phi_ext));
    cr_assert_eq(conv_three_grid(h, (double[]){1.0, 1.0, 1.2}, 1.25, &r, &e), 0);
    cr_assert_eq(r.kind, CONV_INDETERMINATE);
    cr_assert_eq(conv_three_grid((double[]){1, 1, 2}, (double[]){1, 2, 3}, 1.25, &r, &e), ERR_INPUT);
}

/* Report documents: a figure drawn by gnuplot is inlined in the HTML page
 * and referenced by the Markdown page. */
#include <stdio.h>
#include <string.h>

#include "campaign/plot.h"
#include "campaign/report_doc.h"
#include "helpers/th.h"

Test(report, figure_table_markdown_html)
{
    const char *dir = th_temp_dir();
    double x[3] = {2, 4, 8}, y[3] = {3846, 3801, 3650};
    struct plot_spec ps = {.title = "wave speed",
                           .xlabel = "cell edge h (Å)",
                           .ylabel = "wave speed (m/s)",
                           .nseries = 1,
                           .series = {{"DPD/MPM-grid", x, y, 3, PLOT_LINESPOINTS}},
                           .overlay = "3846",
                           .overlay_label = "DPD-only"};
    char svg[1024];
    snprintf(svg, sizeof svg, "%s/fig.svg", dir);
    struct err e = {0};
    cr_assert_eq(plot_svg(&ps, svg, &e), 0, "%s", e.msg);
    struct rdoc *d = rdoc_create("Study <x> & y");
    rdoc_heading(d, 1, "wave_speed");
    rdoc_para(d, "observed order p = %.3f", 1.234);
    const char *hdr[2] = {"h (Å)", "value | m/s"};
    const char *cells[4] = {"2", "3846", "4", "3801"};
    rdoc_table(d, 2, hdr, 2, cells);
    rdoc_figure(d, dir, "fig.svg", "wave speed against cell edge");
    char md[1024], html[1024];
    snprintf(md, sizeof md, "%s/r.md", dir);
    snprintf(html, sizeof html, "%s/r.html", dir);
    cr_assert_eq(rdoc_write_markdown(d, md, &e), 0);
    cr_assert_eq(rdoc_write_html(d, html, &e), 0);
    rdoc_destroy(&d);
    static char buf[200000];
    FILE *f = fopen(html, "r");
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    buf[n] = '\0';
    fclose(f);
    cr_assert(strstr(buf, "<svg") && !strstr(buf, "<?xml"), "SVG must be inline without prolog");
    cr_assert(strstr(buf, "Study &lt;x&gt; &amp; y"));
    cr_assert(strstr(buf, "<td class=\"n\">3801</td>"), "numbers are right-aligned cells");
    f = fopen(md, "r");
    n = fread(buf, 1, sizeof buf - 1, f);
    buf[n] = '\0';
    fclose(f);
    cr_assert(strstr(buf, "![wave speed against cell edge](fig.svg)"));
    cr_assert(strstr(buf, "| value \\| m/s |"), "%s", buf);
}
