// quadcast-codegen -- rewrites generated/ from the templates, or checks that it is in sync
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <set>
#include <sstream>
#include <string>

#include <unistd.h>

#include "quadcast/codegen/generate.hpp"

namespace fs = std::filesystem;

namespace {

int usage() {
    std::cerr << "usage: quadcast-codegen --out DIR     write every generated file under DIR (removes stale ones)\n"
                 "       quadcast-codegen --check DIR   regenerate into a temporary directory, print a unified diff\n"
                 "                                      against DIR and exit 1 when they differ\n";
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
            const fs::path tmp = fs::temp_directory_path() / ("quadcast-codegen-" + std::to_string(::getpid()));
            fs::remove_all(tmp);
            write_tree(tmp, files);
            if (fs::exists(dir / "README.md")) fs::copy_file(dir / "README.md", tmp / "README.md");
            const std::string cmd = "diff -ruN '" + dir.string() + "' '" + tmp.string() + "'";
            const int rc = std::system(cmd.c_str());
            fs::remove_all(tmp);
            if (rc != 0) {
                std::cerr << "quadcast-codegen: " << dir.string() << " is out of date; run `make regenerate` and commit the result\n";
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
