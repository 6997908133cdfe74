/* vtk_util.cpp - VTK's messages kept for ours, and mesh file names (see vtk_util.hpp). */
#include "vtk_util.hpp"

#include <vtkLogger.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkOutputWindow.h>

#include <cctype>
#include <mutex>
#include <string>

namespace tpvtk {
thread_local std::string t_vtk_error;
}

using tpvtk::t_vtk_error;

namespace {


/* "ERROR: In <file>, line <n>\n<Class> (<address>): <text>\n\n" -> "<text>" */
std::string vtk_message_text(const char* raw)
{
    std::string s = raw ? raw : "";
    if (s.compare(0, 10, "ERROR: In ") == 0) {
        size_t nl = s.find('\n');
        s = nl == std::string::npos ? std::string() : s.substr(nl + 1);
    }
    size_t p = s.find("): ");
    if (p != std::string::npos && p < 128)
        s = s.substr(p + 3);
    size_t end = s.find("\n\n"); /* the executive appends a whole vtkInformation dump */
    if (end != std::string::npos)
        s.resize(end);
    while (!s.empty() && (s.back() == '\n' || s.back() == ' '))
        s.pop_back();
    return s;
}

class CaptureOutputWindow : public vtkOutputWindow {
  public:
    static CaptureOutputWindow* New();
    vtkTypeMacro(CaptureOutputWindow, vtkOutputWindow);
    void DisplayText(const char*) override
    {
    }
    void DisplayErrorText(const char* text) override
    {
        if (t_vtk_error.empty())
            t_vtk_error = vtk_message_text(text);
    }
    void DisplayWarningText(const char*) override
    {
    }
    void DisplayGenericWarningText(const char*) override
    {
    }
    void DisplayDebugText(const char*) override
    {
    }

  protected:
    CaptureOutputWindow() = default;
};
vtkStandardNewMacro(CaptureOutputWindow);

} // namespace

namespace tpvtk {

void quiet_vtk()
{
    static std::once_flag once;
    std::call_once(once, [] {
        vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
        vtkNew<CaptureOutputWindow> w;
        vtkOutputWindow::SetInstance(w);
    });
}

std::string lower_ext(const std::string& path)
{
    size_t slash = path.find_last_of('/'), dot = path.find_last_of('.');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash))
        return std::string();
    std::string e = path.substr(dot);
    for (char& c : e)
        c = (char)std::tolower((unsigned char)c);
    return e;
}

tp_mesh_format format_of(const std::string& path)
{
    /* the one decision (output_format.cpp), for the files written and read back alike */
    tp_output_format f;
    return tp_output_format_for(path.c_str(), TP_OUTPUT_MESH, &f, nullptr) == TP_OK
               ? f.mesh
               : TP_MESH_DEFAULT;
}

} // namespace tpvtk
