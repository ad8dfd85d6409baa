#include "core/output_set.h"

#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "core/error.h"

namespace patchsim {

namespace fs = std::filesystem;

// One path to remove if the process is interrupted. Nodes are pushed onto a lock-free list and
// never freed, so the signal handler can walk it at any moment; `live` turns false once the path
// is committed or cleaned up normally.
struct CleanupNode {
    char* path = nullptr;
    bool folder = false;
    std::atomic<bool> live{true};
    CleanupNode* next = nullptr;
};

namespace {

std::atomic<CleanupNode*> cleanupList{nullptr};

CleanupNode* registerCleanup(const std::string& path, bool folder) {
    auto* node = new CleanupNode;
    node->path = ::strdup(path.c_str());
    node->folder = folder;
    node->next = cleanupList.load();
    while (!cleanupList.compare_exchange_weak(node->next, node)) {
    }
    return node;
}

void retire(CleanupNode* node) {
    if (node) node->live.store(false);
}

// Newest first: files, then folders (inner folders were made after their parents).
extern "C" void cleanUpAndReraise(int signal) {
    for (CleanupNode* n = cleanupList.load(); n; n = n->next)
        if (n->live.load() && !n->folder) ::unlink(n->path);
    for (CleanupNode* n = cleanupList.load(); n; n = n->next)
        if (n->live.load() && n->folder) ::rmdir(n->path);
    std::signal(signal, SIG_DFL);
    std::raise(signal);
}

// The same file however it is written ("out/x", "./out/x", "out/../out/x").
std::string identityOf(const std::string& path) {
    std::error_code ec;
    const fs::path p = fs::weakly_canonical(fs::absolute(path, ec), ec);
    return p.lexically_normal().string();
}

bool blank(const std::string& name) {
    return name.find_first_not_of(" \t\n\r") == std::string::npos;
}

std::string quoted(const fs::path& p) {
    return "'" + p.string() + "'";
}

// The first existing ancestor of `p` (or "." for a relative path with none).
fs::path existingAncestor(fs::path p) {
    std::error_code ec;
    while (!p.empty() && !fs::exists(p, ec)) p = p.parent_path();
    return p.empty() ? fs::path(".") : p;
}

}  // namespace

void installInterruptCleanup() {
    static const bool installed = [] {
        for (int signal : {SIGINT, SIGTERM, SIGHUP}) std::signal(signal, cleanUpAndReraise);
        return true;
    }();
    (void)installed;
}

std::string joinOutputPath(const std::string& dir, const std::string& name) {
    if (dir.empty()) throw InputError(dir, "", "empty folder name");
    return (fs::path(dir) / name).string();
}

OutputSet::~OutputSet() {
    if (committed_) return;
    std::error_code ec;
    for (const Entry& e : files_) {
        fs::remove(e.temporary, ec);
        retire(e.cleanup);
    }
    for (auto it = createdFolders_.rbegin(); it != createdFolders_.rend(); ++it) {
        fs::remove(it->first, ec);  // only if empty
        retire(it->second);
    }
}

void OutputSet::folder(const std::string& path, const std::string& field) {
    std::error_code ec;
    if (blank(path)) throw InputError(path, field, "empty folder name");
    const fs::path dir(path);
    if (fs::exists(dir, ec)) {
        if (!fs::is_directory(dir, ec))
            throw InputError(path, field, "is a file, not a folder for the outputs");
    } else {
        const fs::path ancestor = existingAncestor(dir);
        if (!fs::is_directory(ancestor, ec))
            throw InputError(path, field,
                             "cannot make the folder: " + quoted(ancestor) + " is a file");
        std::vector<fs::path> missing;
        for (fs::path p = dir; !p.empty() && !fs::exists(p, ec); p = p.parent_path())
            missing.insert(missing.begin(), p);
        for (const fs::path& p : missing) {
            if (!fs::create_directory(p, ec) && ec)
                throw InputError(path, field, "cannot make the folder: " + ec.message());
            createdFolders_.emplace_back(p.string(), registerCleanup(p.string(), true));
        }
    }
    if (::access(dir.c_str(), W_OK) != 0)
        throw InputError(path, field, "the folder is not writable");
}

std::string OutputSet::file(const std::string& path, const std::string& field) {
    std::error_code ec;
    const fs::path p(path);
    if (blank(path) || blank(p.filename().string()))
        throw InputError(path, field, "empty output file name");
    if (fs::is_directory(p, ec)) throw InputError(path, field, "is a folder; give a file name");
    const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
    if (!fs::exists(dir, ec))
        throw InputError(path, field, "folder " + quoted(dir) + " does not exist");
    if (!fs::is_directory(dir, ec))
        throw InputError(path, field, quoted(dir) + " is a file, not a folder");
    if (::access(dir.c_str(), W_OK) != 0)
        throw InputError(path, field, "folder " + quoted(dir) + " is not writable");
    const std::string identity = identityOf(path);
    for (const Input& in : inputs_)
        if (in.identity == identity)
            throw InputError(path, field, "is the file " + in.field + " names, which is read");
    for (const Entry& e : files_) {
        if (e.identity != identity) continue;
        if (e.field == field) return e.temporary;
        throw InputError(path, field, "is written as " + e.field + " too");
    }
    // Hidden, in the same folder (rename stays on one file system), same extension (image format).
    std::string name = p.stem().string();
    name.insert(0, 1, '.');
    name.append(".tmp-patchsim-").append(std::to_string(::getpid())).append(p.extension().string());
    const fs::path temporary = dir / name;
    files_.push_back(
        {path, temporary.string(), registerCleanup(temporary.string(), false), field, identity});
    return temporary.string();
}

void OutputSet::input(const std::string& path, const std::string& field) {
    if (!path.empty() && path.rfind("builtin:", 0) != 0)
        inputs_.push_back({identityOf(path), field});
}

void OutputSet::writeText(const std::string& path, const std::string& field,
                          const std::function<void(std::ostream&)>& write) {
    const std::string temporary = file(path, field);
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) throw InputError(path, field, "cannot write the file");
    write(out);
    out.flush();
    if (!out) throw InputError(path, field, "error while writing the file");
}

void OutputSet::commit() {
    for (const Entry& e : files_) {
        std::error_code ec;
        fs::rename(e.temporary, e.path, ec);
        if (ec)
            throw InputError(e.path, "",
                             "cannot move the finished file into place: " + ec.message());
        retire(e.cleanup);
    }
    for (const auto& [folder, node] : createdFolders_) retire(node);
    committed_ = true;
}

void writeFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write,
                         const std::string& field) {
    OutputSet outputs;
    outputs.writeText(path, field, write);
    outputs.commit();
}

}  // namespace patchsim
