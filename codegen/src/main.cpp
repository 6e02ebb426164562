// quadcast-codegen -- rewrites generated/ from the templates, or checks that it is in sync
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "quadcast/codegen/generate.hpp"

namespace fs = std::filesystem;

namespace {

int usage() {
    std::cerr << "usage: quadcast-codegen --out DIR     write every generated file under DIR (removes stale ones)\n"
                 "       quadcast-codegen --check DIR   compare DIR with what the templates produce now; print each\n"
                 "                                      changed file and its first differing lines, exit 1 when any differ\n";
    return 2;
}

/// Writes `files` under `dir`, removing files there that are no longer generated.
void write_tree(const fs::path& dir, const std::map<std::string, std::string>& files) {
    std::set<fs::path> keep;
    for (const auto& [rel, text] : files) {
        const fs::path p = dir / rel;
        keep.insert(p.lexically_normal());
        fs::create_directories(p.parent_path());
        std::ifstream old(p, std::ios::binary);
        std::stringstream ss;
        if (old) ss << old.rdbuf();
        if (old && ss.str() == text) continue;
        const fs::path tmp = p.string() + ".tmp";
        {
            std::ofstream out(tmp, std::ios::binary);
            out << text;
            if (!out) throw std::runtime_error("cannot write " + tmp.string());
        }
        fs::rename(tmp, p);
    }
    if (fs::exists(dir))
        for (const auto& e : fs::recursive_directory_iterator(dir))
            if (e.is_regular_file() && !keep.count(e.path().lexically_normal()) && e.path().filename() != "README.md")
                fs::remove(e.path());
}

/// Splits `text` into lines (without the newlines).
std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);) out.push_back(l);
    return out;
}

/// The first hunk where `old_text` and `new_text` differ: up to 3 lines of context, then up to 6
/// removed and 6 added lines (a summary, not a full diff).
std::string first_hunk(const std::string& old_text, const std::string& new_text) {
    const auto a = lines_of(old_text), b = lines_of(new_text);
    std::size_t i = 0;
    while (i < a.size() && i < b.size() && a[i] == b[i]) ++i;
    std::size_t ea = a.size(), eb = b.size();
    while (ea > i && eb > i && a[ea - 1] == b[eb - 1]) { --ea; --eb; }
    std::ostringstream h;
    h << "  @@ line " << i + 1 << ": " << ea - i << " line(s) removed, " << eb - i << " added\n";
    for (std::size_t k = i >= 3 ? i - 3 : 0; k < i; ++k) h << "    " << a[k] << "\n";
    for (std::size_t k = i; k < ea && k < i + 6; ++k) h << "  - " << a[k] << "\n";
    if (ea - i > 6) h << "  - ... (" << ea - i - 6 << " more)\n";
    for (std::size_t k = i; k < eb && k < i + 6; ++k) h << "  + " << b[k] << "\n";
    if (eb - i > 6) h << "  + ... (" << eb - i - 6 << " more)\n";
    return h.str();
}

/// One summary per file of `dir` that differs from `files` (changed, missing or stale).
std::vector<std::string> check_tree(const fs::path& dir, const std::map<std::string, std::string>& files) {
    std::vector<std::string> out;
    std::set<fs::path> keep;
    for (const auto& [rel, text] : files) {
        const fs::path p = dir / rel;
        keep.insert(p.lexically_normal());
        std::ifstream in(p, std::ios::binary);
        if (!in) { out.push_back("missing: " + rel + "\n"); continue; }
        std::stringstream ss;
        ss << in.rdbuf();
        if (ss.str() != text) out.push_back("changed: " + rel + "\n" + first_hunk(ss.str(), text));
    }
    if (fs::exists(dir))
        for (const auto& e : fs::recursive_directory_iterator(dir))
            if (e.is_regular_file() && !keep.count(e.path().lexically_normal()) && e.path().filename() != "README.md")
                out.push_back("stale (no longer generated): " + fs::relative(e.path(), dir).string() + "\n");
    return out;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 3) return usage();
    const std::string mode = argv[1];
    const fs::path dir = argv[2];
    try {
        const auto files = quadcast::codegen::generate_all();
        if (mode == "--out") {
            write_tree(dir, files);
            std::cout << "quadcast-codegen: " << files.size() << " files in " << dir.string() << "\n";
            return 0;
        }
        if (mode == "--check") {
            const auto changes = check_tree(dir, files);
            if (!changes.empty()) {
                for (const std::string& c : changes) std::cout << c;
                std::cerr << "quadcast-codegen: " << changes.size() << " file(s) in " << dir.string()
                          << " out of date; run `make regenerate` and commit the result\n";
                return 1;
            }
            std::cout << "quadcast-codegen: " << files.size() << " generated files in sync\n";
            return 0;
        }
    } catch (const std::exception& e) {
        std::cerr << "quadcast-codegen: " << e.what() << "\n";
        return 1;
    }
    return usage();
}
