"""Request → result logic shared by the front ends (the CLI now, the web explorer later)."""
