"""Set-up in layers: the platforms table and what each layer installs."""
