#pragma once
// The files one command writes, made together or not at all.
//
// Representation
// --------------
// A list of reserved output paths, each with the temporary it is written to first (in the same
// folder, with the same extension, so image writers pick the format from it), plus the folders the
// set created. Paths are checked when they are reserved, before any work is done: a folder must
// be a folder (created if missing), a file's name must not be a folder, the folder must be
// writable, and no file may be reserved by two options or be one of the command's inputs; each
// problem is an InputError naming the path and the option it came from. A name that is empty or
// only blanks is refused, never taken for the current folder. `commit`
// renames every temporary into place; a set destroyed without committing (the command failed)
// removes its temporaries and the folders it created, so a failure leaves nothing behind.
//
// Interrupts: every temporary and created folder is also listed in a process-wide cleanup list
// that a SIGINT, SIGTERM or SIGHUP handler (installInterruptCleanup) walks with unlink and rmdir
// only, the calls a signal handler may make, before the signal ends the process as it would have.

#include <functional>
#include <ostream>
#include <string>
#include <vector>

namespace patchsim {

struct CleanupNode;  // an entry of the interrupt cleanup list (output_set.cpp)

class OutputSet {
  public:
    OutputSet() = default;
    ~OutputSet();
    OutputSet(const OutputSet&) = delete;
    OutputSet& operator=(const OutputSet&) = delete;

    // A folder for outputs, made now if missing. `field` names where the path came from ("-o").
    void folder(const std::string& path, const std::string& field);
    // Reserves the file `path`; returns the temporary to write it to. A path reserved again under
    // the same field gives the same temporary; under another field, or naming a file the command
    // reads (`input`), it is refused: one output must not overwrite another, nor an input.
    std::string file(const std::string& path, const std::string& field);
    // A file the command reads (a scene, a cage, a hardware or grid file), named by `field`.
    void input(const std::string& path, const std::string& field);
    // Reserves `path` and writes it through `write`.
    void writeText(const std::string& path, const std::string& field,
                   const std::function<void(std::ostream&)>& write);
    // Renames every temporary to its final name.
    void commit();

  private:
    struct Entry {
        std::string path, temporary;
        CleanupNode* cleanup;
        std::string field, identity;  // the option it came from; its absolute, normal form
    };
    struct Input {
        std::string identity, field;
    };
    std::vector<Entry> files_;
    std::vector<Input> inputs_;
    std::vector<std::pair<std::string, CleanupNode*>> createdFolders_;  // outermost first
    bool committed_ = false;
};

// `name` inside the output folder `dir` (which must not be empty: "" is refused, not taken as /).
std::string joinOutputPath(const std::string& dir, const std::string& name);

// Installs the handlers that remove every live temporary and created folder when the process is
// interrupted. Idempotent; call once at start-up.
void installInterruptCleanup();

// Writes one file through an OutputSet of its own.
void writeFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write,
                         const std::string& field = {});

}  // namespace patchsim
