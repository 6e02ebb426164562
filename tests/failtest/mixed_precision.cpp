// tests/failtest/mixed_precision.cpp -- must NOT compile: a traced float times a double literal
#include "quadcast/codegen/expr.hpp"

int main() {
    quadcast::codegen::Recorder rec;
    quadcast::codegen::Recording scope(rec);
    quadcast::codegen::Expr a(1.0f);
    quadcast::codegen::Expr b = a * 2.0;
    return static_cast<int>(b.id);
}
