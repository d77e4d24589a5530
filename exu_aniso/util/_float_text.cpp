// Rows of doubles as CSV text, each number written as Python's repr() writes it: the shortest
// digits that read back to the same double, laid out by Python's rules. Built by setup.py as the
// optional extension exu_aniso.util._float_text; exu_aniso.util.output.csv_rows falls back to
// repr() in Python without it, with the same bytes (tests/test_output.py compares the two).
//
// Python's repr (float_repr_style "short", format code 'r'): with the shortest round-trip digits
// d1 d2 ... dn and the decimal point after position decpt (value = 0.d1...dn x 10^decpt),
//   decpt <= -4 or decpt > 16  ->  scientific: d1[.d2...dn]e<sign><at least two exponent digits>
//   otherwise                  ->  fixed, with ".0" when there is no fractional digit
// and nan, inf, -inf for the non-finite values (a NaN's sign is not written).
// std::to_chars(chars_format::scientific) without a precision gives the shortest digits that
// round-trip, the one nearest the value when several are as short, as Python's dtoa mode 0 does.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <string>

namespace py = pybind11;

static void put_repr(std::string &out, double x) {
    if (std::isnan(x)) { out += "nan"; return; }
    if (std::isinf(x)) { out += x < 0 ? "-inf" : "inf"; return; }
    char buf[40];
    const auto res = std::to_chars(buf, buf + sizeof buf, x, std::chars_format::scientific);
    const char *p = buf;
    if (*p == '-') { out += '-'; ++p; }
    char digits[20];
    int n = 0;
    while (p < res.ptr && *p != 'e') {
        if (*p != '.') digits[n++] = *p;
        ++p;
    }
    // the exponent, "e+05" -> 5, "e-307" -> -307 (to_chars writes no terminating zero)
    const bool negative_exponent = p + 1 < res.ptr && p[1] == '-';
    int exp10 = 0;
    for (const char *q = p + 2; q < res.ptr; ++q) exp10 = 10 * exp10 + (*q - '0');
    if (negative_exponent) exp10 = -exp10;
    const int decpt = exp10 + 1;
    if (decpt <= -4 || decpt > 16) {
        out += digits[0];
        if (n > 1) { out += '.'; out.append(digits + 1, n - 1); }
        char e[8];
        const int a = exp10 < 0 ? -exp10 : exp10;
        const int len = std::snprintf(e, sizeof e, "e%c%02d", exp10 < 0 ? '-' : '+', a);
        out.append(e, len);
    } else if (decpt <= 0) {
        out += "0.";
        out.append(-decpt, '0');
        out.append(digits, n);
    } else if (decpt >= n) {
        out.append(digits, n);
        out.append(decpt - n, '0');
        out += ".0";
    } else {
        out.append(digits, decpt);
        out += '.';
        out.append(digits + decpt, n - decpt);
    }
}

// values: a 2-D float64 array (any strides); one line per row, the numbers separated by commas,
// every line ended by "\n".
static py::bytes csv_rows(py::array_t<double, py::array::forcecast> values) {
    if (values.ndim() != 2) throw std::invalid_argument("csv_rows: values must be a 2-D array");
    const auto v = values.unchecked<2>();
    std::string out;
    out.reserve(static_cast<size_t>(v.shape(0)) * static_cast<size_t>(v.shape(1)) * 20 + 1);
    for (py::ssize_t i = 0; i < v.shape(0); ++i) {
        for (py::ssize_t j = 0; j < v.shape(1); ++j) {
            if (j) out += ',';
            put_repr(out, v(i, j));
        }
        out += '\n';
    }
    return py::bytes(out);
}

PYBIND11_MODULE(_float_text, m) {
    m.doc() = "Rows of doubles as CSV text, each number as Python's repr() writes it";
    m.def("csv_rows", &csv_rows, py::arg("values"));
}
