"""Independent numpy references for the chapter images (the book's maintainers page,
'How a picture is checked')."""
