# The front door of the course in PowerShell (the Developer PowerShell for VS 2022):
# .\course.ps1 <verb> [options], as ./course on Linux and macOS. Run .\course.ps1 --help.
# All this does is find Python 3.10 or newer (the py launcher first, then python on
# PATH) and hand the verb to tools\course.py, which sets up what the verb needs and
# carries it out in the course's .venv.
$course = Join-Path $PSScriptRoot "tools\course.py"
foreach ($candidate in @(@("py", "-3"), @("python"))) {
    $program = $candidate[0]
    $first = @($candidate | Select-Object -Skip 1)
    if (-not (Get-Command $program -ErrorAction SilentlyContinue)) { continue }
    & $program @first -c "import sys; sys.exit(sys.version_info < (3, 10))" 2>$null
    if ($LASTEXITCODE -ne 0) { continue }
    & $program @first $course @args
    exit $LASTEXITCODE
}
[Console]::Error.WriteLine("course: Python 3.10 or newer is needed: winget install --id Python.Python.3.12 --exact")
exit 7
