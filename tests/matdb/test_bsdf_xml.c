/* BSDF XML (Klems): the basis against its definition, the figures of real
 * files as WINDOW writes, genBSDF writes and the IGSDB serves them against
 * the figures LBNL's WinCalc publishes for the same files, a Lambertian
 * layer against its analytic figures, Rows against Columns, write/read
 * round trips, and refusals that name the file, the line and the element. */
#include "vr_test.h"
#include "vr/bsdf_xml.h"

#include <sys/stat.h>

/* ---------------------------------------------------------------------- */
/* The basis */

static void klems_full_basis(void **state) {
  (void)state;
  vr_klems_basis b;
  vr_klems_full(&b);
  /* 145 patches (LBNL/Klems Full, as every WINDOW file spells it out). */
  assert_int_equal(b.n, 145);
  /* Projected solid angles of a hemisphere's patches sum to pi (analytic:
   * the integral of cos theta over the hemisphere). */
  double sum = 0;
  for (int p = 0; p < b.n; p++) sum += vr_klems_lambda(&b, p);
  assert_near(sum, M_PI, 1e-12);
  /* The normal patch: pi sin^2(5 deg). */
  assert_near(vr_klems_lambda(&b, 0), M_PI * pow(sin(5 * M_PI / 180), 2), 1e-15);
  /* Lookup: a ring holds (lo, hi]; azimuth patches are centred on k 360/nphi. */
  assert_int_equal(vr_klems_patch(&b, 0, 123), 0);
  assert_int_equal(vr_klems_patch(&b, 5, 0), 0);
  assert_int_equal(vr_klems_patch(&b, 15, 270), 7);     /* WinCalc's theta=15 phi=270 case */
  assert_int_equal(vr_klems_patch(&b, 15.001, 0), 9);   /* ring 3 starts at 9 */
  assert_int_equal(vr_klems_patch(&b, 10, 22.4), 1);    /* ring 2: 45 deg wide, first centred on 0 */
  assert_int_equal(vr_klems_patch(&b, 10, 22.6), 2);
  assert_int_equal(vr_klems_patch(&b, 10, -10), 1);     /* azimuth modulo 360 */
  assert_int_equal(vr_klems_patch(&b, 10, 350), 1);
  assert_int_equal(vr_klems_patch(&b, 90, 0), 133);     /* the last ring, 75-90 */
  assert_int_equal(vr_klems_patch(&b, 90.5, 0), -1);
  assert_int_equal(vr_klems_patch(&b, NAN, 0), -1);
  double t, p;
  vr_klems_direction(&b, 7, &t, &p);
  assert_near(t, 10, 0);
  assert_near(p, 270, 1e-12);
  vr_klems_direction(&b, 144, &t, &p);
  assert_near(t, 82.5, 0);
  assert_near(p, 330, 1e-12);
}

/* ---------------------------------------------------------------------- */
/* Real files against WinCalc */

/* LBNL-ETA/WinCalc (commit 65e615a3b8b53653cacc4b47cee0deb82b98408d),
 * test/expected_results/1_layer/<case>/full_basis/condensed_spectrum/<angle>/
 * {photopic,solar}.json, system_results: for front T, front R, back T, back
 * R in turn, direct_direct, direct_hemispherical, diffuse_diffuse.  WinCalc
 * reads the same files (test/products/) with OpticsParser; a single BSDF
 * layer's photopic figures are the file's Visible band, its solar figures
 * the Solar band. */
static const struct {
  const char *file;
  double theta, phi;
  const char *band;
  double v[12];
} WINCALC[] = {
    {"SquareSlat_genBSDF.xml.gz", 0, 0, "Visible",
     {0.13045978664615859, 0.31047899463815931, 0.19011247429513742, 0.0032502189612303883,
      0.53444278802489242, 0.62467658541814663, 0.12107100233275553, 0.30602150895903779,
      0.19209819763273847, 0.0030237980335798059, 0.52691485082073919, 0.6218487458582016}},
    {"SquareSlat_genBSDF.xml.gz", 0, 0, "Solar",
     {0.13065093669152977, 0.31122031241939202, 0.19169548739528611, 0.002822338772278562,
      0.4968299860776102, 0.58513463304383928, 0.12080563547825784, 0.30551218604571262,
      0.19350663571839982, 0.0024768129911389358, 0.48843914148877132, 0.58261480991907444}},
    {"SquareSlat_genBSDF.xml.gz", 15, 270, "Visible",
     {0.0025234634544103384, 0.18908915013271468, 0.19011247429513742, 0.003750152584868357,
      0.60302368490875602, 0.62467658541814663, 0.0025858987499125844, 0.19642492311047144,
      0.19209819763273847, 0.0039553471047894459, 0.59811512825572288, 0.6218487458582016}},
    {"SquareSlat_genBSDF.xml.gz", 15, 270, "Solar",
     {0.0026650098901231261, 0.1893151048843332, 0.19169548739528611, 0.0037208357501853835,
      0.56483809009974639, 0.58513463304383928, 0.0026957960649692091, 0.19702842428494888,
      0.19350663571839982, 0.0036271011769229535, 0.55927162148579201, 0.58261480991907444}},
    {"cgdb_14060_urban_loft_river_stone.xml.gz", 0, 0, "Visible",
     {0.003698407351007535, 0.31800287586056214, 0.246313677036473, 2.5510536641913129e-05,
      0.40134578783980862, 0.45324411384354257, 0.0038853573454441558, 0.31846106825432041,
      0.24673804723626364, 0.0011467332247463533, 0.41331982422947433, 0.46657226487345993}},
    {"cgdb_14060_urban_loft_river_stone.xml.gz", 0, 0, "Solar",
     {0.0053583820271642041, 0.34156801257842329, 0.26831541954438021, 5.9659814410461039e-05,
      0.39908528877389821, 0.45114962900638467, 0.006467195473871268, 0.34229958084906281,
      0.26900517271855545, 0.0022473136170647755, 0.41150532826127711, 0.46571233567973919}},
    {"cgdb_14060_urban_loft_river_stone.xml.gz", 15, 270, "Visible",
     {0.0035703100134758217, 0.31522578456060479, 0.246313677036473, 2.9410126121902054e-05,
      0.4033776079616419, 0.45324411384354257, 0.0037507823020811169, 0.31568378286086324,
      0.24673804723626364, 0.0012027598763731081, 0.41540565486431225, 0.46657226487345993}},
    {"cgdb_14060_urban_loft_river_stone.xml.gz", 15, 270, "Solar",
     {0.0051728003827936405, 0.33877153946930133, 0.26831541954438021, 6.6773347412375593e-05,
      0.40112304288444678, 0.45114962900638467, 0.0062432030301883251, 0.33950516897895855,
      0.26900517271855545, 0.0023371138051526104, 0.41362754480563019, 0.46571233567973919}},
    {"cgdb_46016_seatex_midnight.xml.gz", 0, 0, "Visible",
     {0.038528260418424186, 0.059276745102103866, 0.034641993651924136, 8.9489721615691531e-06,
      0.08213615912054377, 0.10900078433331199, 0.038528260418424186, 0.059276745102103866,
      0.034641993651924136, 8.9489721615691531e-06, 0.08213615912054377, 0.10900078433331199}},
    {"cgdb_46016_seatex_midnight.xml.gz", 0, 0, "Solar",
     {0.03827406188118411, 0.21878431976483098, 0.157948681536145, 2.8111704550209243e-05,
      0.35441721846775986, 0.40700290229356811, 0.03827406188118411, 0.21878431976483098,
      0.157948681536145, 2.8111704550209243e-05, 0.35441721846775986, 0.40700290229356811}},
    {"cgdb_46016_seatex_midnight.xml.gz", 15, 270, "Visible",
     {0.03757979736594376, 0.05801070105530063, 0.034641993651924136, 1.0868452635056589e-05,
      0.083187596934001018, 0.10900078433331199, 0.03757979736594376, 0.05801070105530063,
      0.034641993651924136, 1.0868452635056589e-05, 0.083187596934001018, 0.10900078433331199}},
    {"cgdb_46016_seatex_midnight.xml.gz", 15, 270, "Solar",
     {0.037329962892495863, 0.21625316539426928, 0.157948681536145, 3.2395452167582847e-05,
      0.35647557904847854, 0.40700290229356811, 0.037329962892495863, 0.21625316539426928,
      0.157948681536145, 3.2395452167582847e-05, 0.35647557904847854, 0.40700290229356811}},
};

static void real_files_match_wincalc(void **state) {
  (void)state;
  static const vr_bsdf_side ORDER[4] = {VR_BSDF_TF, VR_BSDF_RF, VR_BSDF_TB, VR_BSDF_RB};
  for (size_t c = 0; c < sizeof WINCALC / sizeof WINCALC[0]; c++) {
    char path[512];
    snprintf(path, sizeof path, "%s/bsdf/%s", VR_TEST_DATA, WINCALC[c].file);
    vr_bsdf_xml *x;
    vr_error err = {0};
    if (vr_bsdf_xml_read(path, &x, &err)) fail_msg("%s", err.message);
    assert_int_equal(x->basis.n, 145);
    assert_int_equal(x->nbands, 2);
    const vr_bsdf_band *b = vr_bsdf_xml_band(x, WINCALC[c].band);
    assert_non_null(b);
    int in = vr_klems_patch(&x->basis, WINCALC[c].theta, WINCALC[c].phi);
    for (int k = 0; k < 4; k++) {
      assert_non_null(b->m[ORDER[k]]);
      vr_klems_figures f;
      vr_klems_figures_of(&x->basis, b->m[ORDER[k]], in, &f);
      /* Same sums as WinCalc's of the same numbers: only rounding differs. */
      assert_near(f.direct_direct, WINCALC[c].v[3 * k], 1e-12);
      assert_near(f.direct_hemispherical, WINCALC[c].v[3 * k + 1], 1e-12);
      assert_near(f.diffuse_diffuse, WINCALC[c].v[3 * k + 2], 1e-12);
      assert_near(f.direct_diffuse, f.direct_hemispherical - f.direct_direct, 1e-15);
    }
    vr_bsdf_xml_destroy(x);
  }
}

static void real_file_metadata(void **state) {
  (void)state;
  char path[512];
  snprintf(path, sizeof path, "%s/bsdf/cgdb_14060_urban_loft_river_stone.xml.gz", VR_TEST_DATA);
  vr_bsdf_xml *x;
  vr_error err = {0};
  if (vr_bsdf_xml_read(path, &x, &err)) fail_msg("%s", err.message);
  /* As the file's <Material> says. */
  assert_string_equal(x->name, "Urban Loft River Stone");
  assert_string_equal(x->manufacturer, "Hunter Douglas");
  assert_near(x->thickness_mm, 0.381, 1e-12);
  assert_string_equal(vr_bsdf_xml_band(x, "visible")->detector, "ASTM E308 1931 Y.dsp");
  vr_bsdf_xml_destroy(x);
  /* genBSDF's file: no namespace, a byte-order mark, the thickness in metres. */
  snprintf(path, sizeof path, "%s/bsdf/SquareSlat_genBSDF.xml.gz", VR_TEST_DATA);
  if (vr_bsdf_xml_read(path, &x, &err)) fail_msg("%s", err.message);
  assert_string_equal(x->device_type, "Louvered Shutter");
  assert_near(x->thickness_mm, 26, 1e-9);
  vr_bsdf_xml_destroy(x);
}

/* ---------------------------------------------------------------------- */
/* Small files written here */

/* A two-ring basis (0-45 deg one patch, 45-90 two) with one block per
 * entry of `blocks` (direction, then 9 numbers or any text). */
static char *small_file(const char *structure, const char *basis_extra, const char *blocks) {
  static char buf[8192];
  snprintf(buf, sizeof buf,
           "<?xml version=\"1.0\"?>\n"
           "<WindowElement xmlns=\"http://windows.lbl.gov\">\n"
           "<Optical><Layer>\n"
           "<Material><Name>test</Name><Thickness unit=\"Millimeter\">4</Thickness></Material>\n"
           "<DataDefinition>\n"
           "<IncidentDataStructure>%s</IncidentDataStructure>\n"
           "<AngleBasis><AngleBasisName>two rings</AngleBasisName>\n"
           "<AngleBasisBlock><Theta>0</Theta><nPhis>1</nPhis>"
           "<ThetaBounds><LowerTheta>0</LowerTheta><UpperTheta>45</UpperTheta></ThetaBounds></AngleBasisBlock>\n"
           "<AngleBasisBlock><Theta>67.5</Theta><nPhis>2</nPhis>"
           "<ThetaBounds><LowerTheta>45</LowerTheta><UpperTheta>90</UpperTheta></ThetaBounds></AngleBasisBlock>\n"
           "%s</AngleBasis>\n"
           "</DataDefinition>\n%s"
           "</Layer></Optical></WindowElement>\n",
           structure, basis_extra, blocks);
  return buf;
}

#define BLOCK(dir, data)                                                                           \
  "<WavelengthData><Wavelength unit=\"Integral\">Visible</Wavelength><WavelengthDataBlock>\n"     \
  "<WavelengthDataDirection>" dir "</WavelengthDataDirection>\n"                                  \
  "<ColumnAngleBasis>two rings</ColumnAngleBasis><RowAngleBasis>two rings</RowAngleBasis>\n"      \
  "<ScatteringDataType>BTDF</ScatteringDataType>\n"                                               \
  "<ScatteringData>\n" data "\n</ScatteringData>\n</WavelengthDataBlock></WavelengthData>\n"

static vr_status parse(const char *text, vr_bsdf_xml **x, vr_error *err) {
  return vr_bsdf_xml_parse(text, strlen(text), "small.xml", x, err);
}

/* A Lambertian layer, BSDF rho/pi everywhere: every direct-hemispherical
 * and the diffuse-diffuse figure are rho (the projected solid angles of a
 * hemisphere sum to pi), on any basis. */
static void lambertian_layer(void **state) {
  (void)state;
  const double rho = 0.6;
  char data[512];
  snprintf(data, sizeof data, "%.17g %.17g %.17g\n%.17g %.17g %.17g\n%.17g %.17g %.17g", rho / M_PI,
           rho / M_PI, rho / M_PI, rho / M_PI, rho / M_PI, rho / M_PI, rho / M_PI, rho / M_PI,
           rho / M_PI);
  char blocks[2048];
  snprintf(blocks, sizeof blocks,
           "<WavelengthData><Wavelength unit=\"Integral\">Visible</Wavelength><WavelengthDataBlock>"
           "<WavelengthDataDirection>Reflection Front</WavelengthDataDirection>"
           "<ScatteringData>%s</ScatteringData></WavelengthDataBlock></WavelengthData>",
           data);
  vr_bsdf_xml *x;
  vr_error err = {0};
  if (parse(small_file("Columns", "", blocks), &x, &err)) fail_msg("%s", err.message);
  assert_int_equal(x->basis.n, 3);
  const vr_bsdf_band *b = vr_bsdf_xml_band(x, "Visible");
  assert_null(b->m[VR_BSDF_TF]);
  for (int in = 0; in < 3; in++) {
    vr_klems_figures f;
    vr_klems_figures_of(&x->basis, b->m[VR_BSDF_RF], in, &f);
    assert_near(f.direct_hemispherical, rho, 1e-14);
    assert_near(f.diffuse_diffuse, rho, 1e-14);
    /* direct-direct: the incident patch's share, rho Lambda_i / pi. */
    assert_near(f.direct_direct, rho * vr_klems_lambda(&x->basis, in) / M_PI, 1e-15);
  }
  /* Ring 1 spans 0-45 deg: Lambda = pi sin^2 45 = pi/2; ring 2's two
   * patches pi/4 each. */
  assert_near(vr_klems_lambda(&x->basis, 0), M_PI / 2, 1e-15);
  assert_near(vr_klems_lambda(&x->basis, 2), M_PI / 4, 1e-15);
  vr_bsdf_xml_destroy(x);
}

/* "Columns": each column an incident direction; "Rows": each row. */
static void rows_and_columns(void **state) {
  (void)state;
  vr_bsdf_xml *c, *r;
  vr_error err = {0};
  const char *data = "1, 2, 3,\n4, 5, 6,\n7, 8, 9";
  char blocks[2048];
  snprintf(blocks, sizeof blocks, BLOCK("Transmission Front", "%s"), data);
  if (parse(small_file("Columns", "", blocks), &c, &err)) fail_msg("%s", err.message);
  if (parse(small_file("Rows", "", blocks), &r, &err)) fail_msg("%s", err.message);
  const double *mc = c->bands[0].m[VR_BSDF_TF], *mr = r->bands[0].m[VR_BSDF_TF];
  /* Columns: m[out][in] is the text's row out, column in. */
  assert_near(mc[0 * 3 + 1], 2, 0);
  assert_near(mc[1 * 3 + 0], 4, 0);
  for (int o = 0; o < 3; o++)
    for (int i = 0; i < 3; i++) assert_near(mr[o * 3 + i], mc[i * 3 + o], 0);
  /* Incident patch 1 (ring 2) exits through patch 1 straight: 5 Lambda_1. */
  vr_klems_figures f;
  vr_klems_figures_of(&c->basis, mc, 1, &f);
  assert_near(f.direct_direct, 5 * M_PI / 4, 1e-14);
  assert_near(f.direct_hemispherical, 2 * M_PI / 2 + 5 * M_PI / 4 + 8 * M_PI / 4, 1e-13);
  vr_bsdf_xml_destroy(c);
  vr_bsdf_xml_destroy(r);
}

/* Files that give only the ring centres: a basis LBNL defines is known by
 * its name (Radiance's src/common/bsdf_m.c tabulates the same three, and
 * refuses any other without bounds); Klems Half's rings are 0-6.5-19.5-
 * 32.5-45.5-58.5-71.5-90 deg with 1, 8, 12, 16, 20, 12, 8 azimuths (77
 * patches).  Another name without bounds is refused. */
static void basis_without_bounds(void **state) {
  (void)state;
  char text[4096], blocks[512] = "";
  const char *head =
      "<WindowElement><Optical><Layer><DataDefinition>"
      "<IncidentDataStructure>Columns</IncidentDataStructure><AngleBasis><AngleBasisName>%s"
      "</AngleBasisName>";
  static const double C[7] = {0, 13, 26, 39, 52, 65, 80.75};
  static const int P[7] = {1, 8, 12, 16, 20, 12, 8};
  for (int k = 0; k < 7; k++)
    snprintf(blocks + strlen(blocks), sizeof blocks - strlen(blocks),
             "<AngleBasisBlock><Theta>%g</Theta><nPhis>%d</nPhis></AngleBasisBlock>", C[k], P[k]);
  const char *tail =
      "</AngleBasis></DataDefinition><WavelengthData><Wavelength unit=\"Nanometer\">550</Wavelength>"
      "<WavelengthDataBlock><WavelengthDataDirection>Transmission Back</WavelengthDataDirection>"
      "<ScatteringData>0</ScatteringData></WavelengthDataBlock></WavelengthData>"
      "</Layer></Optical></WindowElement>";
  int len = snprintf(text, sizeof text, head, "LBNL/Klems Half");
  snprintf(text + len, sizeof text - (size_t)len, "%s%s", blocks, tail);
  vr_bsdf_xml *x;
  vr_error err = {0};
  /* The data hold one value: the basis is read first, then the count refused. */
  assert_int_equal(parse(text, &x, &err), VR_E_PARSE);
  assert_contains(err.message, "a 77-patch basis needs 77 x 77");
  vr_klems_basis b;
  assert_true(vr_klems_named("lbnl/klems half", &b));
  assert_int_equal(b.n, 77);
  assert_near(b.theta_lo[3], 32.5, 0);
  assert_near(b.theta_hi[6], 90, 0);
  double sum = 0;
  for (int p = 0; p < b.n; p++) sum += vr_klems_lambda(&b, p);
  assert_near(sum, M_PI, 1e-12);
  assert_true(vr_klems_named("LBNL/Klems Quarter", &b));
  assert_int_equal(b.n, 41);
  len = snprintf(text, sizeof text, head, "my basis");
  snprintf(text + len, sizeof text - (size_t)len, "%s%s", blocks, tail);
  assert_int_equal(parse(text, &x, &err), VR_E_PARSE);
  assert_contains(err.message, "gives no <ThetaBounds>");
}

/* A basis of more patches than VR_KLEMS_MAX_PATCHES is refused before any
 * matrix is allocated (a small file could otherwise ask for terabytes). */
static void huge_basis_refused(void **state) {
  (void)state;
  const char *text =
      "<WindowElement><Optical><Layer><DataDefinition>"
      "<IncidentDataStructure>Columns</IncidentDataStructure><AngleBasis><AngleBasisName>big"
      "</AngleBasisName><AngleBasisBlock><Theta>0</Theta><nPhis>1</nPhis><ThetaBounds>"
      "<LowerTheta>0</LowerTheta><UpperTheta>10</UpperTheta></ThetaBounds></AngleBasisBlock>"
      "<AngleBasisBlock><Theta>50</Theta><nPhis>100000</nPhis><ThetaBounds><LowerTheta>10"
      "</LowerTheta><UpperTheta>90</UpperTheta></ThetaBounds></AngleBasisBlock></AngleBasis>"
      "</DataDefinition><WavelengthData><Wavelength unit=\"Integral\">Visible</Wavelength>"
      "<WavelengthDataBlock><WavelengthDataDirection>Transmission Front</WavelengthDataDirection>"
      "<ScatteringData>0</ScatteringData></WavelengthDataBlock></WavelengthData>"
      "</Layer></Optical></WindowElement>";
  vr_bsdf_xml *x;
  vr_error err = {0};
  assert_int_equal(parse(text, &x, &err), VR_E_RANGE);
  assert_contains(err.message, "100001 patches; at most 1024");
}

/* ---------------------------------------------------------------------- */
/* Refusals */

static void refused(const char *text, const char *needle1, const char *needle2) {
  vr_bsdf_xml *x = (vr_bsdf_xml *)1;
  vr_error err = {0};
  vr_status st = parse(text, &x, &err);
  if (st == VR_OK) fail_msg("accepted; expected an error with '%s'", needle1);
  assert_null(x);
  assert_contains(err.message, "small.xml:");
  assert_contains(err.message, needle1);
  if (needle2) assert_contains(err.message, needle2);
}

static void bad_files(void **state) {
  (void)state;
  const char *nine = "1 2 3 4 5 6 7 8 9";
  char blocks[4096];
  /* Truncated XML: libxml2's message with the line. */
  refused("<WindowElement><Optical>\n<Layer>", "malformed XML", NULL);
  refused("<Window/>", "not <WindowElement>", NULL);
  /* Too few numbers (line 16 holds <ScatteringData> in the layout above). */
  snprintf(blocks, sizeof blocks, BLOCK("Transmission Front", "1 2 3"));
  refused(small_file("Columns", "", blocks), "holds 3 values", "3 x 3 = 9");
  /* A number that is not, on its own line (the data's second line, 18). */
  snprintf(blocks, sizeof blocks, BLOCK("Transmission Front", "1 2 3\n4 x 6\n7 8 9"));
  refused(small_file("Columns", "", blocks), "small.xml:18:", "value 5 'x'");
  snprintf(blocks, sizeof blocks, BLOCK("Transmission Front", "1 2 3 4 nan 6 7 8 9"));
  refused(small_file("Columns", "", blocks), "value 5 'nan'", NULL);
  snprintf(blocks, sizeof blocks, BLOCK("Transmission Front", "1 2 3 4 -0.5 6 7 8 9"));
  refused(small_file("Columns", "", blocks), "value 5 '-0.5'", ">= 0");
  snprintf(blocks, sizeof blocks, BLOCK("Transmission Sideways", "%s"), nine);
  refused(small_file("Columns", "", blocks), "<WavelengthDataDirection> 'Transmission Sideways'", NULL);
  snprintf(blocks, sizeof blocks, BLOCK("Reflection Back", "%s") BLOCK("Reflection Back", "%s"), nine,
           nine);
  refused(small_file("Columns", "", blocks), "given twice", NULL);
  snprintf(blocks, sizeof blocks, BLOCK("Transmission Front", "%s"), nine);
  /* A tensor tree that holds a Klems matrix's numbers. */
  refused(small_file("TensorTree4", "", blocks), "(TensorTree4): expected '{'", NULL);
  refused(small_file("Diagonal", "", blocks), "expected Columns or Rows", NULL);
  /* A third ring that overlaps the second. */
  refused(small_file("Columns",
                     "<AngleBasisBlock><Theta>80</Theta><nPhis>2</nPhis><ThetaBounds><LowerTheta>70"
                     "</LowerTheta><UpperTheta>90</UpperTheta></ThetaBounds></AngleBasisBlock>",
                     blocks),
          "ring 3 spans [70, 90]", NULL);
  refused(small_file("Columns",
                     "<AngleBasisBlock><Theta>95</Theta><nPhis>2.5</nPhis></AngleBasisBlock>", blocks),
          "<nPhis> 2.5", NULL);
  /* A block on a basis the file does not define. */
  char other[4096];
  snprintf(other, sizeof other, "%s", blocks);
  char *p = strstr(other, "<ColumnAngleBasis>two rings");
  memcpy(p + strlen("<ColumnAngleBasis>"), "one ring!", 9);
  refused(small_file("Columns", "", other), "<ColumnAngleBasis> 'one ring!", NULL);
  /* No data at all. */
  refused(small_file("Columns", "", ""), "no <WavelengthData>", NULL);
  /* A missing file names itself. */
  vr_bsdf_xml *x;
  vr_error err = {0};
  assert_int_equal(vr_bsdf_xml_read("/nonexistent/shade.xml", &x, &err), VR_E_IO);
  assert_contains(err.message, "/nonexistent/shade.xml");
}

/* ---------------------------------------------------------------------- */
/* Writing */

static void write_read_round_trip(void **state) {
  (void)state;
  vr_klems_basis b;
  vr_klems_full(&b);
  vr_bsdf_xml *x;
  vr_error err = {0};
  assert_int_equal(vr_bsdf_xml_create(&b, 2, &x, &err), VR_OK);
  snprintf(x->name, sizeof x->name, "pane <A> & \"B\"");
  snprintf(x->bands[0].name, sizeof x->bands[0].name, "Visible");
  snprintf(x->bands[1].name, sizeof x->bands[1].name, "560");
  x->bands[1].nm = 560;
  x->thickness_mm = 6;
  for (int s = 0; s < VR_BSDF_SIDES; s++)
    for (int i = 0; i < b.n; i++)
      for (int o = 0; o < b.n; o++)
        x->bands[0].m[s][o * b.n + i] = x->bands[1].m[s][o * b.n + i] =
            (s + 1) * 0.01 + 1e-3 * ((o * 7 + i * 3) % 11) + (o == i ? 12.345678901 : 0);
  char path[] = "/tmp/vr_bsdf_XXXXXX.xml";
  int fd = mkstemps(path, 4);
  assert_true(fd >= 0);
  close(fd);
  if (vr_bsdf_xml_write(path, x, &err)) fail_msg("%s", err.message);
  vr_bsdf_xml *y;
  if (vr_bsdf_xml_read(path, &y, &err)) fail_msg("%s", err.message);
  assert_string_equal(y->name, x->name);
  assert_near(y->thickness_mm, 6, 0);
  assert_int_equal(y->nbands, 2);
  assert_near(y->bands[1].nm, 560, 0);
  for (size_t k = 0; k < 2; k++)
    for (int s = 0; s < VR_BSDF_SIDES; s++)
      for (int j = 0; j < b.n * b.n; j++)
        assert_rel(y->bands[k].m[s][j], x->bands[k].m[s][j], 1e-9); /* written to 9 digits */
  vr_bsdf_xml_destroy(y);
  /* A NaN is refused and the file already there is left as it was. */
  struct stat before, after;
  assert_int_equal(stat(path, &before), 0);
  x->bands[0].m[VR_BSDF_RB][5] = NAN;
  assert_int_equal(vr_bsdf_xml_write(path, x, &err), VR_E_RANGE);
  assert_contains(err.message, "Reflection Back");
  assert_contains(err.message, "nothing written");
  assert_int_equal(stat(path, &after), 0);
  assert_int_equal(after.st_size, before.st_size);
  assert_int_equal(vr_bsdf_xml_read(path, &y, &err), VR_OK);
  vr_bsdf_xml_destroy(y);
  vr_bsdf_xml_destroy(x);
  unlink(path);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(klems_full_basis),       cmocka_unit_test(real_files_match_wincalc),
      cmocka_unit_test(real_file_metadata),     cmocka_unit_test(lambertian_layer),
      cmocka_unit_test(rows_and_columns),       cmocka_unit_test(basis_without_bounds),
      cmocka_unit_test(bad_files),              cmocka_unit_test(write_read_round_trip),
      cmocka_unit_test(huge_basis_refused),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
