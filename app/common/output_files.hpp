#pragma once
// Every file a command writes goes through one OutputFiles, so nothing a user owns is lost and
// nothing half-written is left behind:
//   - each output is declared before the command's work starts and checked then: it is not a
//     file the command reads (std::filesystem::equivalent, so a symlink or hard link to an input
//     counts), not another output, has an extension that fits what is written, is not a folder,
//     and its folder exists and takes a new file (InputError naming the path otherwise);
//   - declaring it creates an empty temporary beside it (that is the writability check), the
//     command writes into the temporary, and commit() renames every temporary into place only
//     after all were written;
//   - a failure (an exception, so the object is destroyed uncommitted) removes the temporaries
//     and any folder the object created; so does SIGINT, SIGTERM, SIGHUP or SIGQUIT while the
//     object lives, before the signal takes its usual course (see the constructor);
//   - an existing file whose permission bits allow no writing is refused, not replaced.
// `render`, `convert`, `bench` and the window's screenshot, render and tf-export all use it.
#include <functional>
#include <list>
#include <string>
#include <vector>

namespace prismoid::app {

class OutputFiles {
 public:
  // Installs the clean-up on those signals for as long as the outermost OutputFiles lives: the
  // handler removes the temporaries and created folders of every live OutputFiles, then does
  // what the disposition it replaced did (the default: end the process by the signal; a
  // handler of the program's own, such as the window's close request: call it). A signal that
  // was ignored stays ignored.
  OutputFiles();
  // Uncommitted: removes the temporaries and the folders this object created.
  ~OutputFiles();
  OutputFiles(const OutputFiles&) = delete;
  OutputFiles& operator=(const OutputFiles&) = delete;

  // A file the command reads; paths that name no file (field:NAME, presets, the default
  // dataset) are ignored. A .pvtu, .vtm, .mhd or .pvd also reads the files it names, a numbered
  // series ('flow_*.vtu') its steps. InputError when
  // an output already declared is this file.
  void input(const std::string& path);
  // Declares output `path`, written for `option` (named in messages: "--stats", "convert"),
  // whose extension must be one of `extensions` (lower case, with the dot). Checks it and
  // creates its temporary now.
  void output(const std::string& path, const std::string& option, const std::vector<std::string>& extensions);
  // Declares a folder that outputs go into (bench --out): an existing folder, or created now
  // with its missing parents (and removed again, if still empty, unless committed).
  void folder(const std::string& path, const std::string& option);

  // Writes declared output `path` (spelled as declared) through `writer`, which gets the
  // temporary's path (with the output's own extension) and throws on failure.
  void write(const std::string& path, const std::function<void(const std::string& temporary)>& writer);
  // Gives up declared output `path` (spelled as declared): its temporary is removed and
  // commit() leaves it out. For an optional output that failed (a bench plot).
  void discard(const std::string& path);
  // Renames every temporary onto its output (signals held meanwhile, so a signal does not land
  // between two renames). std::logic_error when a declared output was never written.
  void commit();

 private:
  struct Input {
    std::string path, resolved;
  };
  struct Output {
    std::string path, option, resolved, temporary;
    bool written = false;
  };
  void check_not_input(const Output& out, const Input& in) const;

  std::list<Input> inputs_;
  std::list<Output> outputs_;          // std::list: the temporaries' strings never move (the signal handler reads them)
  std::list<std::string> folders_;     // created by this object, outermost first
  bool committed_ = false;
};

// The images a render writes: .png (display colour) or .pfm (the numbers).
inline const std::vector<std::string> kImageExtensions = {".png", ".pfm"};

// The checks output() makes, with nothing left behind: for an action that writes later (the
// window's screenshot, taken when the frame finishes). InputError as OutputFiles::output.
void check_output(const std::string& path, const std::string& option, const std::vector<std::string>& extensions,
                  const std::vector<std::string>& inputs);

}  // namespace prismoid::app
