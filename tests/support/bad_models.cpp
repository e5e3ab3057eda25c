#include "support/bad_models.h"

namespace shapespline::test {

namespace {

// Valid point sets the entries below break one rule at a time.
const std::string kP3 = R"([[0,0],[1,2],[3,3]])";
const std::string kP5 = R"([[0,0],[1,2],[3,3],[5,1],[6,4]])";
const std::string kP8 = R"([[0,0],[1,2],[3,3],[5,1],[6,4],[8,3],[9,0],[11,1]])";
// 4 x 4 surface net.
const std::string kNet4 =
    R"([[[0,0,0],[1,0,0],[2,0,1],[3,0,0]],[[0,1,0],[1,1,1],[2,1,1],[3,1,0]],)"
    R"([[0,2,0],[1,2,1],[2,2,1],[3,2,0]],[[0,3,0],[1,3,0],[2,3,1],[3,3,0]]])";

std::string curve(const std::string& construction, const std::string& rest) {
  return R"({"kind": "curve", "construction": ")" + construction + "\", " + rest + "}";
}
// A bicubic bspline surface's keys before "points" (kNet4 is 4 x 4), over the domain [0, 1]^2.
const std::string kTrimmable = R"("order": [4, 4], "knots": [[0,0,0,0,1,1,1,1],[0,0,0,0,1,1,1,1]], )";

std::string surface(const std::string& construction, const std::string& rest) {
  return R"({"kind": "surface", "construction": ")" + construction + "\", " + rest + "}";
}
std::string xw(const std::string& rest) { return curve("extended_bspline", R"("degree": 4, )" + rest); }

std::vector<BadModel> build() {
  const std::string pts5 = "\"points\": " + kP5;
  const std::string pts8 = "\"points\": " + kP8;
  const std::string bs4 = R"("order": 4, "closed": false, )";
  return {
      // Document level.
      {"malformed_truncated", R"({"kind": "curve", "construction": )", "(document)"},
      {"malformed_trailing_garbage", xw("\"lambda\": 0, " + pts5) + " x", "(document)"},
      {"malformed_nan_literal", xw("\"lambda\": NaN, " + pts5), "(document)"},
      {"malformed_empty_text", "", "(document)"},
      {"not_an_object", "[1, 2, 3]", "(document)"},
      {"duplicate_key", xw("\"lambda\": 0, \"lambda\": 0.5, " + pts5), "lambda"},
      // kind / construction / keys.
      {"missing_kind", R"({"construction": "gb", "points": )" + kP5 + "}", "kind"},
      {"unknown_kind", R"({"kind": "volume", "construction": "gb", "points": )" + kP5 + "}", "kind"},
      {"missing_construction", R"({"kind": "curve", "points": )" + kP5 + "}", "construction"},
      {"unknown_construction", curve("nurbs", pts5), "construction"},
      {"unknown_key", curve("gb", pts5 + R"(, "weights": [1,1,1,1,1])"), "weights"},
      {"alpha_on_extended_bspline", xw("\"alpha\": 0.5, " + pts5), "alpha"},
      {"knots_on_alpha_eb", curve("alpha_eb", R"("degree": 4, "alpha": 0.5, "knots": [0,1,2,3,4], )" + pts5), "knots"},
      {"mu_on_ubp", curve("ubp", R"("order": 4, "mu": [0.25, 0.5, 0.5], )" + pts5), "mu"},
      {"degree_on_gb", curve("gb", R"("degree": 4, )" + pts5), "degree"},
      {"order_on_extended_bspline", xw(R"("order": 4, )" + pts5), "order"},
      {"lambda_on_gubp", curve("gubp", R"("order": 3, "mu": [0.25, 0.75], "lambda": 0, )" + pts5), "lambda"},
      {"lambda_on_bspline", curve("bspline", R"("order": 4, "lambda": 0.5, )" + pts5), "lambda"},
      {"span_knots_on_surface", surface("extended_bspline", R"("degree": 4, "knots": [0,1], "points": )" + kNet4), "knots"},
      {"name_not_string", curve("gb", R"("name": 5, )" + pts5), "name"},
      // Required keys.
      {"missing_points", xw(R"("lambda": 0)"), "points"},
      {"missing_degree", curve("extended_bspline", pts5), "degree"},
      {"missing_order", curve("ubp", pts5), "order"},
      {"missing_mu", curve("gubp", R"("order": 5, )" + pts8), "mu"},
      {"missing_alpha", curve("alpha_eb", R"("degree": 4, )" + pts5), "alpha"},
      // Integers and numbers.
      {"degree_7", curve("extended_bspline", R"("degree": 7, "lambda": 0, )" + pts5), "degree"},
      {"degree_3", curve("alpha_eb", R"("degree": 3, "alpha": 0.5, )" + pts5), "degree"},
      {"degree_fractional", curve("extended_bspline", R"("degree": 4.5, )" + pts5), "degree"},
      {"degree_string", curve("extended_bspline", R"("degree": "5", )" + pts5), "degree"},
      {"order_fractional", curve("ubp", R"("order": 4.5, )" + pts8), "order"},
      {"order_string", curve("ubp", R"("order": "5", )" + pts8), "order"},
      {"order_huge", curve("ubp", R"("order": 1e300, )" + pts8), "order"},
      {"ubp_order_2", curve("ubp", R"("order": 2, "lambda": 0, )" + pts8), "order"},
      {"ubp_order_11", curve("ubp", R"("order": 11, )" + pts8 + R"(, "closed": true)"), "order"},
      {"gubp_order_2", curve("gubp", R"("order": 2, "mu": [0.5, 1], )" + pts8), "order"},
      {"bspline_order_1", curve("bspline", R"("order": 1, )" + pts5), "order"},
      {"lambda_string_nan", xw(R"("lambda": "NaN", )" + pts5), "lambda"},
      {"lambda_bool", curve("gb", R"("lambda": true, )" + pts5), "lambda"},
      {"coordinate_string", curve("gb", R"("points": [[0,0],[1,"2"],[3,3],[5,1],[6,4]])"), "points[1][1]"},
      {"coordinate_infinity_string", curve("gb", R"("points": [[0,0],[1,2],["Infinity",3],[5,1],[6,4]])"),
       "points[2][0]"},
      {"coordinate_null", curve("gb", R"("points": [[0,0],[1,2],[3,3],[5,null],[6,4]])"), "points[3][1]"},
      // Lambda ranges.
      {"xw_lambda_above_1", xw(R"("lambda": 1.5, )" + pts5), "lambda"},
      {"xw4_lambda_below_m8", xw(R"("lambda": -9, )" + pts5), "lambda"},
      {"xw5_lambda_below_m15", curve("extended_bspline", R"("degree": 5, "lambda": -15.25, )" + pts5), "lambda"},
      {"xw6_lambda_below_m24", curve("alpha_eb", R"("degree": 6, "lambda": -24.5, "alpha": 0.5, )" + pts5), "lambda"},
      {"gb_lambda_m10", curve("gb", R"("lambda": -10, )" + pts5), "lambda"},
      {"gb_lambda_m12_pole", curve("gb", R"("lambda": -12, )" + pts5), "lambda"},
      {"gb_lambda_m20", curve("gb", R"("lambda": -20, )" + pts5), "lambda"},
      {"ubp5_lambda_m11", curve("ubp", R"("order": 5, "lambda": -11, )" + pts8), "lambda"},
      {"ubp5_lambda_just_below_min", curve("ubp", R"("order": 5, "lambda": -10.7476635514019, )" + pts8), "lambda"},
      {"ubp_lambda_above_1", curve("ubp", R"("order": 4, "lambda": 1.0625, )" + pts8), "lambda"},
      {"ubp10_lambda_m23_5", curve("ubp", R"("order": 10, "lambda": -23.5, "closed": true, )" + pts8), "lambda"},
      // mu.
      {"mu_wrong_length", curve("gubp", R"("order": 5, "mu": [0.5, 0.5], )" + pts8), "mu"},
      {"mu_parity_sums_order5", curve("gubp", R"("order": 5, "mu": [0.5, 0.5, 0.5], )" + pts8), "mu"},
      {"mu_parity_sums_order4", curve("gubp", R"("order": 4, "mu": [0.25, 0.5, 0.25], )" + pts8), "mu"},
      {"mu_value_out_of_range", curve("gubp", R"("order": 3, "mu": [1.5, -0.5], )" + pts8), "mu[0]"},
      {"mu_not_array", curve("gubp", R"("order": 3, "mu": 0.5, )" + pts8), "mu"},
      // alpha.
      {"alpha_zero", curve("alpha_eb", R"("degree": 4, "alpha": 0, )" + pts5), "alpha"},
      {"alpha_above_1", curve("alpha_eb", R"("degree": 5, "alpha": 1.25, )" + pts5), "alpha"},
      {"alpha_negative_in_array", curve("alpha_eb", R"("degree": 4, "alpha": [0.5, 0.5, 0.5, -0.25, 0.5], )" + pts5),
       "alpha[3]"},
      {"alpha_above_1_in_array", curve("alpha_eb", R"("degree": 4, "alpha": [0.5, 1.0001, 0.5, 0.5, 0.5], )" + pts5),
       "alpha[1]"},
      {"alpha_length", curve("alpha_eb", R"("degree": 4, "alpha": [0.5, 0.5, 0.5], )" + pts5), "alpha"},
      {"alpha_string", curve("alpha_eb", R"("degree": 4, "alpha": "0.5", )" + pts5), "alpha"},
      {"surface_alpha_row_length",
       surface("alpha_eb", R"("degree": 4, "alpha": [[0.5,0.5,0.5,0.5],[0.5,0.5,0.5],[0.5,0.5,0.5,0.5],[0.5,0.5,0.5,0.5]], "points": )" + kNet4),
       "alpha[1]"},
      {"surface_alpha_zero_entry",
       surface("alpha_eb", R"("degree": 4, "alpha": [[0.5,0.5,0.5,0.5],[0.5,0.5,0.5,0.5],[0.5,0,0.5,0.5],[0.5,0.5,0.5,0.5]], "points": )" + kNet4),
       "alpha[2][1]"},
      // Point shapes.
      {"points_not_array", curve("gb", R"("points": 5)"), "points"},
      {"point_not_array", curve("gb", R"("points": [[0,0],[1,2],3,[5,1],[6,4]])"), "points[2]"},
      {"point_one_coordinate", curve("gb", R"("points": [[0,0],[1,2],[3],[5,1],[6,4]])"), "points[2]"},
      {"point_four_coordinates", curve("gb", R"("points": [[0,0,0,0],[1,2,0,0],[3,3,0,0],[5,1,0,0]])"), "points[0]"},
      {"mixed_dimensions", curve("gb", R"("points": [[0,0],[1,2],[3,3,1],[5,1],[6,4]])"), "points[2]"},
      {"surface_ragged_rows",
       surface("extended_bspline",
               R"("degree": 4, "points": [[[0,0,0],[1,0,0],[2,0,0],[3,0,0]],[[0,1,0],[1,1,0],[2,1,0]],[[0,2,0],[1,2,0],[2,2,0],[3,2,0]],[[0,3,0],[1,3,0],[2,3,0],[3,3,0]]])"),
       "points[1]"},
      {"surface_2d_points", surface("extended_bspline", R"("degree": 4, "points": [[[0,0],[1,0]],[[0,1],[1,1]]])"),
       "points[0][0]"},
      {"surface_row_not_array", surface("alpha_eb", R"("degree": 4, "alpha": 0.5, "points": [[[0,0,0],[1,0,0]], 7])"),
       "points[1]"},
      {"surface_closed_bool", surface("extended_bspline", R"("degree": 4, "closed": true, "points": )" + kNet4),
       "closed"},
      {"closed_not_bool", curve("gb", R"("closed": "yes", )" + pts5), "closed"},
      // Point counts.
      {"xw_open_3_points", xw("\"points\": " + kP3), "points"},
      {"gb_open_3_points", curve("gb", "\"points\": " + kP3), "points"},
      {"ubp6_open_5_points", curve("ubp", R"("order": 6, )" + pts5), "points"},
      {"gubp5_open_4_points", curve("gubp", R"("order": 5, "mu": [0.25, 0.5, 0.25], "points": [[0,0],[1,2],[3,3],[5,1]])"),
       "points"},
      {"bspline4_open_3_points", curve("bspline", "\"order\": 4, \"points\": " + kP3), "points"},
      {"alpha_eb_open_1_point", curve("alpha_eb", R"("degree": 4, "alpha": 0.5, "points": [[0,0]])"), "points"},
      {"closed_curve_2_points", curve("alpha_eb", R"("degree": 4, "alpha": 0.5, "closed": true, "points": [[0,0],[1,0]])"),
       "points"},
      {"empty_points", curve("gb", R"("points": [])"), "points"},
      {"surface_alpha_eb_one_row", surface("alpha_eb", R"("degree": 4, "alpha": 0.5, "points": [[[0,0,0],[1,0,0],[2,0,0]]])"),
       "points"},
      {"surface_ubp_too_few_columns",
       surface("ubp", R"("order": 4, "points": [[[0,0,0],[1,0,0],[2,0,0]],[[0,1,0],[1,1,0],[2,1,0]],[[0,2,0],[1,2,0],[2,2,0]],[[0,3,0],[1,3,0],[2,3,0]]])"),
       "points[0]"},
      {"surface_closed_v_two_columns",
       surface("alpha_eb", R"("degree": 4, "alpha": 0.5, "closed": [false, true], "points": [[[0,0,0],[1,0,0]],[[0,1,0],[1,1,0]]])"),
       "points[0]"},
      // Span knots.
      {"span_knots_not_increasing", curve("gb", R"("lambda": 2.5, "knots": [0, 1, 1], )" + pts5), "knots[2]"},
      {"span_knots_decreasing", xw(R"("knots": [0, 2, 1], )" + pts5), "knots[2]"},
      {"span_knots_wrong_length", curve("gb", R"("knots": [0, 1, 2, 3], )" + pts5), "knots"},
      {"span_knots_closed_wrong_length", curve("gb", R"("closed": true, "knots": [0, 1, 2], )" + pts5), "knots"},
      {"span_knots_not_numbers", curve("gb", R"("knots": [0, "1", 2], )" + pts5), "knots[1]"},
      // B-spline knot vectors.
      {"bspline_knot_length", curve("bspline", bs4 + R"("knots": [0,0,0,0,0.5,1,1,1], )" + pts5), "knots"},
      {"bspline_knots_decreasing", curve("bspline", bs4 + R"("knots": [0,0,0,0,0.5,0.25,1,1,1], )" + pts5), "knots[5]"},
      {"bspline_knot_multiplicity", curve("bspline", bs4 + R"("knots": [0,0,0,0,0,1,1,1,1], )" + pts5), "knots[0]"},
      {"bspline_interior_multiplicity", curve("bspline", bs4 + R"("knots": [0,0,0,0,0.5,0.5,0.5,0.5,0.5,1,1,1,1], "points": [[0,0],[1,2],[3,3],[5,1],[6,4],[8,3],[9,0],[11,1],[12,2]])"),
       "knots[4]"},
      {"bspline_empty_domain", curve("bspline", R"("order": 4, "knots": [0,0,0,1,1,1,1,2], "points": [[0,0],[1,2],[3,3],[5,1]])"),
       "knots"},
      {"bspline_closed_with_knots",
       curve("bspline", R"("order": 4, "closed": true, "knots": [0,0,0,0,0.5,1,1,1,1], )" + pts5), "closed"},
      {"bspline_knots_not_array", curve("bspline", bs4 + R"("knots": 1, )" + pts5), "knots"},
      {"bspline_surface_order_three_values",
       surface("bspline", R"("order": [4, 4, 4], "points": )" + kNet4), "order"},
      {"bspline_surface_order_v_11",
       surface("bspline", R"("order": [4, 11], "points": )" + kNet4), "order[1]"},
      {"bspline_surface_knots_not_pair",
       surface("bspline", R"("order": [4, 4], "knots": [0,0,0,0,1,1,1,1], "points": )" + kNet4), "knots"},
      {"bspline_surface_v_knot_length",
       surface("bspline", R"("order": [4, 4], "knots": [[0,0,0,0,1,1,1,1],[0,0,0,0,1,1,1]], "points": )" + kNet4),
       "knots[1]"},
      {"bspline_surface_closed_with_knots",
       surface("bspline",
               R"("order": [4, 4], "closed": [true, false], "knots": [[0,0,0,0,1,1,1,1],[0,0,0,0,1,1,1,1]], "points": )" +
                   kNet4),
       "closed"},
      {"ubp_surface_two_orders", surface("ubp", R"("order": [4, 4], "points": )" + kNet4), "order"},
      // Weights (rational B-splines, docs/format.md Weights).
      {"weights_zero", curve("bspline", bs4 + R"("knots": [0,0,0,0,0.5,1,1,1,1], "weights": [1,0,1,1,1], )" + pts5),
       "weights[1]"},
      {"weights_count", curve("bspline", bs4 + R"("knots": [0,0,0,0,0.5,1,1,1,1], "weights": [1,1], )" + pts5),
       "weights"},
      {"weights_without_knots", curve("bspline", bs4 + R"("weights": [1,1,1,1,1], )" + pts5), "weights"},
      {"weights_on_extended_bspline", xw(R"("weights": [1,1,1,1,1], )" + pts5), "weights"},
      {"weights_negative_surface",
       surface("bspline", R"("order": [4, 4], "knots": [[0,0,0,0,1,1,1,1],[0,0,0,0,1,1,1,1]], )"
                          R"("weights": [[1,1,1,1],[1,1,1,1],[1,1,1,-2],[1,1,1,1]], "points": )" + kNet4),
       "weights[2][3]"},
      // Trimming loops (docs/format.md Trim): bspline surfaces with knot vectors only.
      {"trim_on_curve", curve("bspline", bs4 + R"("knots": [0,0,0,0,0.5,1,1,1,1], "trim": {"loops": [], "tolerance": 0}, )" + pts5),
       "trim"},
      {"trim_without_knots",
       surface("bspline", R"("order": [4, 4], "trim": {"loops": [[[0,0],[1,0],[1,1]]], "tolerance": 0}, "points": )" + kNet4),
       "trim"},
      {"trim_on_ubp", surface("ubp", R"("order": 4, "trim": {"loops": [[[0,0],[1,0],[1,1]]], "tolerance": 0}, "points": )" + kNet4),
       "trim"},
      {"trim_two_points", surface("bspline", kTrimmable + R"("trim": {"loops": [[[0,0],[1,0]]], "tolerance": 0}, "points": )" + kNet4),
       "trim.loops[0]"},
      {"trim_outside_domain",
       surface("bspline", kTrimmable + R"("trim": {"loops": [[[0,0],[1,0],[1,1.5]]], "tolerance": 0.1}, "points": )" + kNet4),
       "trim.loops[0][2]"},
      {"trim_negative_tolerance",
       surface("bspline", kTrimmable + R"("trim": {"loops": [[[0,0],[1,0],[1,1]]], "tolerance": -1}, "points": )" + kNet4),
       "trim.tolerance"},
      {"trim_point_not_pair",
       surface("bspline", kTrimmable + R"("trim": {"loops": [[[0,0],[1,0],[1]]], "tolerance": 0}, "points": )" + kNet4),
       "trim.loops[0][2]"},
      {"trim_unknown_key",
       surface("bspline", kTrimmable + R"("trim": {"loops": [[[0,0],[1,0],[1,1]]], "tolerance": 0, "rule": "winding"}, "points": )" + kNet4),
       "trim.rule"},
      {"trim_no_loops", surface("bspline", kTrimmable + R"("trim": {"loops": [], "tolerance": 0}, "points": )" + kNet4),
       "trim.loops"},
      // Files a model names (docs/format.md "Files a model names"): inside the model file's folder.
      {"points_npy_parent_dir", surface("alpha_eb", R"("degree": 4, "alpha": 0.5, "points": {"npy": "../../../../etc/hostname"})"),
       "points"},
      {"points_npy_absolute", surface("alpha_eb", R"("degree": 4, "alpha": 0.5, "points": {"npy": "/etc/hostname"})"), "points"},
      {"alpha_npy_parent_dir", surface("alpha_eb", R"("degree": 4, "alpha": {"npy": "../alpha.npy"}, "points": )" + kNet4),
       "alpha"},
      {"points_npy_empty_name", curve("alpha_eb", R"("degree": 4, "alpha": 0.5, "points": {"npy": ""})"), "points"},
  };
}

}  // namespace

const std::vector<BadModel>& badModelCatalog() {
  static const std::vector<BadModel> catalog = build();
  return catalog;
}

}  // namespace shapespline::test
