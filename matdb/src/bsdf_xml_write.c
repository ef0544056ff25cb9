/* Writing Klems BSDF XML files (vr/bsdf_xml.h), as LBNL WINDOW writes them:
 * namespace windows.lbl.gov, one System layer, the basis spelled out
 * ring by ring, each band's sides as WavelengthData blocks whose columns
 * are the incident directions. */
#include "vr/bsdf_xml.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vr/atomic_file.h"

vr_status vr_bsdf_xml_create(const vr_klems_basis *b, size_t nbands, vr_bsdf_xml **out,
                             vr_error *err) {
  *out = NULL;
  vr_bsdf_xml *x = calloc(1, sizeof *x);
  if (!x || !(x->bands = calloc(nbands ? nbands : 1, sizeof *x->bands))) {
    free(x);
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  }
  x->basis = *b;
  x->nbands = nbands;
  x->thickness_mm = NAN;
  size_t nn = (size_t)b->n * b->n;
  for (size_t i = 0; i < nbands; i++) {
    x->bands[i].nm = NAN;
    for (int s = 0; s < VR_BSDF_SIDES; s++)
      if (!(x->bands[i].m[s] = calloc(nn, sizeof(double)))) {
        vr_bsdf_xml_destroy(x);
        return vr_error_set(err, VR_E_NOMEM, "out of memory");
      }
  }
  *out = x;
  return VR_OK;
}

/* s with &, <, > and " escaped. */
static void put_text(FILE *f, const char *s) {
  for (; *s; s++) {
    switch (*s) {
    case '&': fputs("&amp;", f); break;
    case '<': fputs("&lt;", f); break;
    case '>': fputs("&gt;", f); break;
    case '"': fputs("&quot;", f); break;
    default: fputc(*s, f);
    }
  }
}

static void put_basis(FILE *f, const vr_klems_basis *b) {
  fprintf(f, "\t\t\t<AngleBasis>\n\t\t\t\t<AngleBasisName>");
  put_text(f, b->name);
  fprintf(f, "</AngleBasisName>\n");
  for (int r = 0; r < b->nrings; r++)
    fprintf(f,
            "\t\t\t\t<AngleBasisBlock>\n\t\t\t\t\t<Theta>%.17g</Theta>\n\t\t\t\t\t<nPhis>%d</nPhis>\n"
            "\t\t\t\t\t<ThetaBounds>\n\t\t\t\t\t\t<LowerTheta>%.17g</LowerTheta>\n"
            "\t\t\t\t\t\t<UpperTheta>%.17g</UpperTheta>\n\t\t\t\t\t</ThetaBounds>\n"
            "\t\t\t\t</AngleBasisBlock>\n",
            b->theta_c[r], b->nphi[r], b->theta_lo[r], b->theta_hi[r]);
  fprintf(f, "\t\t\t</AngleBasis>\n");
}

static void put_block(FILE *f, const vr_bsdf_xml *x, const vr_bsdf_band *band, int side) {
  const double *m = band->m[side];
  int n = x->basis.n;
  fprintf(f, "\t\t<WavelengthData>\n\t\t\t<LayerNumber>System</LayerNumber>\n");
  if (isnan(band->nm)) {
    fprintf(f, "\t\t\t<Wavelength unit=\"Integral\">");
    put_text(f, band->name);
    fprintf(f, "</Wavelength>\n");
  } else {
    fprintf(f, "\t\t\t<Wavelength unit=\"Nanometer\">%.17g</Wavelength>\n", band->nm);
  }
  if (band->detector[0]) {
    fprintf(f, "\t\t\t<DetectorSpectrum>");
    put_text(f, band->detector);
    fprintf(f, "</DetectorSpectrum>\n");
  }
  fprintf(f, "\t\t\t<WavelengthDataBlock>\n\t\t\t\t<WavelengthDataDirection>%s</WavelengthDataDirection>\n",
          vr_bsdf_side_name((vr_bsdf_side)side));
  fprintf(f, "\t\t\t\t<ColumnAngleBasis>");
  put_text(f, x->basis.name);
  fprintf(f, "</ColumnAngleBasis>\n\t\t\t\t<RowAngleBasis>");
  put_text(f, x->basis.name);
  fprintf(f, "</RowAngleBasis>\n\t\t\t\t<ScatteringDataType>%s</ScatteringDataType>\n",
          side == VR_BSDF_TF || side == VR_BSDF_TB ? "BTDF" : "BRDF");
  fprintf(f, "\t\t\t\t<ScatteringData>\n");
  for (int o = 0; o < n; o++) {
    for (int i = 0; i < n; i++) fprintf(f, "%s%.9g", i ? ", " : "", m[(size_t)o * n + i]);
    fputc('\n', f);
  }
  fprintf(f, "\t\t\t\t</ScatteringData>\n\t\t\t</WavelengthDataBlock>\n\t\t</WavelengthData>\n");
}

vr_status vr_bsdf_xml_write(const char *path, const vr_bsdf_xml *x, vr_error *err) {
  for (size_t i = 0; i < x->nbands; i++)
    for (int s = 0; s < VR_BSDF_SIDES; s++) {
      const double *m = x->bands[i].m[s];
      for (size_t k = 0; m && k < (size_t)x->basis.n * x->basis.n; k++)
        if (!(m[k] >= 0) || !isfinite(m[k]))
          return vr_error_set(err, VR_E_RANGE,
                              "%s: band %s, %s: BSDF value %g (patch %zu from patch %zu) is not a "
                              "finite number >= 0; nothing written",
                              path, x->bands[i].name, vr_bsdf_side_name((vr_bsdf_side)s), m[k],
                              k / (size_t)x->basis.n, k % (size_t)x->basis.n);
    }
  vr_atomic_file af;
  if (vr_atomic_file_open(&af, path, err)) return err ? err->status : VR_E_IO;
  FILE *f = af.fp;
  fprintf(f, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
             "<WindowElement xmlns=\"http://windows.lbl.gov\" "
             "xmlns:xsi=\"http://www.w3.org/2001/XMLSchema-instance\" "
             "xsi:schemaLocation=\"http://windows.lbl.gov BSDF-v1.4.xsd\">\n"
             "\t<WindowElementType>System</WindowElementType>\n\t<Optical>\n\t<Layer>\n"
             "\t\t<Material>\n\t\t\t<Name>");
  put_text(f, x->name);
  fprintf(f, "</Name>\n\t\t\t<Manufacturer>");
  put_text(f, x->manufacturer);
  fprintf(f, "</Manufacturer>\n");
  if (!isnan(x->thickness_mm))
    fprintf(f, "\t\t\t<Thickness unit=\"Millimeter\">%.9g</Thickness>\n", x->thickness_mm);
  fprintf(f, "\t\t\t<DeviceType>");
  put_text(f, x->device_type[0] ? x->device_type : "Other");
  fprintf(f, "</DeviceType>\n\t\t</Material>\n\t\t<DataDefinition>\n"
             "\t\t\t<IncidentDataStructure>Columns</IncidentDataStructure>\n");
  put_basis(f, &x->basis);
  fprintf(f, "\t\t</DataDefinition>\n");
  for (size_t i = 0; i < x->nbands; i++)
    for (int s = 0; s < VR_BSDF_SIDES; s++)
      if (x->bands[i].m[s]) put_block(f, x, &x->bands[i], s);
  fprintf(f, "\t</Layer>\n\t</Optical>\n</WindowElement>\n");
  if (ferror(f)) {
    vr_atomic_file_abort(&af);
    return vr_error_set(err, VR_E_IO, "%s: write failed", path);
  }
  return vr_atomic_file_commit(&af, err);
}
