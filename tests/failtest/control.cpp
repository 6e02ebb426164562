// tests/failtest/control.cpp -- compiles: the well-formed twin of the compile-must-fail tests
#include "quadcast/codegen/expr.hpp"

int main() {
    quadcast::codegen::Recorder rec;
    quadcast::codegen::Recording scope(rec);
    quadcast::codegen::Expr a(1.0f), b(2.0f);
    quadcast::codegen::Expr c = select(a < b, a * quadcast::codegen::Expr(2.0), b);
    return static_cast<int>(c.id);
}
