@echo off
rem The front door of the course on Windows (cmd.exe): course <verb> [options], as ./course
rem on Linux and macOS. Run course --help. All this does is find Python 3.10 or newer
rem (the py launcher first, then python on PATH) and hand the verb to tools\course.py,
rem which sets up what the verb needs and carries it out in the course's .venv.
setlocal
set "COURSE_ROOT=%~dp0"
where py >nul 2>nul
if %ERRORLEVEL%==0 (
  py -3 -c "import sys; sys.exit(sys.version_info < (3, 10))" >nul 2>nul
  if not errorlevel 1 (
    py -3 "%COURSE_ROOT%tools\course.py" %*
    exit /b %ERRORLEVEL%
  )
)
where python >nul 2>nul
if %ERRORLEVEL%==0 (
  python -c "import sys; sys.exit(sys.version_info < (3, 10))" >nul 2>nul
  if not errorlevel 1 (
    python "%COURSE_ROOT%tools\course.py" %*
    exit /b %ERRORLEVEL%
  )
)
echo course: Python 3.10 or newer is needed: winget install --id Python.Python.3.12 --exact 1>&2
exit /b 7
