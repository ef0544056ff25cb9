/* The delimited-text reader: fields, positions, and the wording of errors. */
#include "vr_test.h"
#include "vr/csv.h"
#include "vr/file.h"

static void splits_fields_and_keeps_positions(void **state) {
  (void)state;
  const char text[] = "\xEF\xBB\xBF# a comment\r\nnm, T ,R\r\n\n400,0.9,\"0,1\"\r\n  500 ;x\n";
  vr_csv *c;
  vr_error err = {0};
  assert_int_equal(vr_csv_parse(text, sizeof text - 1, "t.csv", &c, &err), VR_OK);
  assert_int_equal(vr_csv_rows(c), 3);
  assert_int_equal(vr_csv_comment_count(c), 1);
  assert_string_equal(vr_csv_comment(c, 0), " a comment");
  assert_string_equal(vr_csv_field(c, 0, 1), "T");
  assert_int_equal(vr_csv_line(c, 1), 4);
  assert_string_equal(vr_csv_field(c, 1, 2), "0,1");
  assert_int_equal(vr_csv_col_pos(c, 1, 2), 9);
  /* Third data row has no comma: one field "500 ;x" on line 5, column 3. */
  assert_int_equal(vr_csv_cols(c, 2), 1);
  assert_int_equal(vr_csv_line(c, 2), 5);
  assert_int_equal(vr_csv_col_pos(c, 2, 0), 3);
  assert_int_equal(vr_csv_find_column(c, 0, "r"), 2);
  assert_int_equal(vr_csv_find_column(c, 0, "Q"), -1);
  vr_csv_destroy(c);
}

static void blank_separated_and_semicolons(void **state) {
  (void)state;
  const char ws[] = "1.0   2.0  3.0\n";
  const char semi[] = "a;b;c\n1;2;3\n";
  vr_csv *c;
  assert_int_equal(vr_csv_parse(ws, sizeof ws - 1, "ws", &c, NULL), VR_OK);
  assert_int_equal(vr_csv_cols(c, 0), 3);
  assert_string_equal(vr_csv_field(c, 0, 2), "3.0");
  vr_csv_destroy(c);
  const char tab[] = "a b\tc\n";
  assert_int_equal(vr_csv_parse(tab, sizeof tab - 1, "tab", &c, NULL), VR_OK);
  assert_int_equal(vr_csv_cols(c, 0), 2);
  assert_string_equal(vr_csv_field(c, 0, 0), "a b");
  vr_csv_destroy(c);
  assert_int_equal(vr_csv_parse(semi, sizeof semi - 1, "semi", &c, NULL), VR_OK);
  assert_int_equal(vr_csv_cols(c, 1), 3);
  vr_csv_destroy(c);
}

static void numbers_report_file_line_column_and_field(void **state) {
  (void)state;
  const char text[] = "nm,T\n400,0.5\n410,abc\n420,nan\n430\n";
  vr_csv *c;
  vr_error err = {0};
  double v;
  assert_int_equal(vr_csv_parse(text, sizeof text - 1, "spec.csv", &c, &err), VR_OK);
  assert_int_equal(vr_csv_number(c, 1, 1, "T", &v, &err), VR_OK);
  assert_near(v, 0.5, 0.0);
  assert_int_equal(vr_csv_number(c, 2, 1, "T", &v, &err), VR_E_PARSE);
  assert_string_equal(err.message, "spec.csv:3:5: field 'T': expected a number, got 'abc'");
  assert_int_equal(vr_csv_number(c, 3, 1, "T", &v, &err), VR_E_RANGE);
  assert_string_equal(err.message, "spec.csv:4:5: field 'T': 'nan' is not a finite number");
  assert_int_equal(vr_csv_number(c, 4, 1, "T", &v, &err), VR_E_PARSE);
  assert_contains(err.message, "spec.csv:5:");
  assert_contains(err.message, "field 'T' (column 2) is missing");
  vr_csv_destroy(c);
}

static void malformed_quotes_and_binary_are_refused(void **state) {
  (void)state;
  vr_csv *c;
  vr_error err = {0};
  const char unterminated[] = "a,b\n1,\"2\n";
  assert_int_equal(vr_csv_parse(unterminated, sizeof unterminated - 1, "q.csv", &c, &err),
                   VR_E_PARSE);
  assert_string_equal(err.message, "q.csv:2:3: unterminated quoted field");
  assert_null(c);
  const char binary[] = "a,b\n1\0,2\n";
  assert_int_equal(vr_csv_parse(binary, sizeof binary - 1, "b.csv", &c, &err), VR_E_PARSE);
  assert_contains(err.message, "NUL byte");
}

static void missing_file_names_itself(void **state) {
  (void)state;
  vr_csv *c;
  vr_error err = {0};
  assert_int_equal(vr_csv_read("/nonexistent/dir/x.csv", &c, &err), VR_E_IO);
  assert_contains(err.message, "/nonexistent/dir/x.csv: cannot open");
}

static void number_lists_and_whole_files(void **state) {
  (void)state;
  double v[3];
  size_t n;
  assert_int_equal(vr_parse_doubles("65, 70,75.5", v, 3, &n), 0);
  assert_int_equal(n, 3);
  assert_near(v[2], 75.5, 0);
  assert_int_not_equal(vr_parse_doubles("65,,70", v, 3, &n), 0);
  assert_int_not_equal(vr_parse_doubles("1,2,3,4", v, 3, &n), 0);
  assert_int_not_equal(vr_parse_doubles("", v, 3, &n), 0);
  const char *path = vr_test_file("abc\n");
  char *text;
  size_t len;
  vr_error err = {0};
  assert_int_equal(vr_read_file(path, 0, &text, &len, &err), VR_OK);
  assert_int_equal(len, 4);
  assert_string_equal(text, "abc\n");
  free(text);
  assert_int_equal(vr_read_file(path, 2, &text, &len, &err), VR_E_RANGE);
  assert_int_equal(vr_read_file("/nonexistent/x", 0, &text, &len, &err), VR_E_IO);
  assert_contains(err.message, "/nonexistent/x");
  unlink(path);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(splits_fields_and_keeps_positions),
      cmocka_unit_test(blank_separated_and_semicolons),
      cmocka_unit_test(numbers_report_file_line_column_and_field),
      cmocka_unit_test(malformed_quotes_and_binary_are_refused),
      cmocka_unit_test(missing_file_names_itself),
      cmocka_unit_test(number_lists_and_whole_files),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
